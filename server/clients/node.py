"""A cooperation-server process for the client tests: started on a free loopback port, waited
for until it accepts connections, and stopped at the end, also when a test fails.

The binary is named by the environment variable ``COOPERATION_SERVER``
(``cargo build --release -p cooperation-server`` builds ``target/release/cooperation-server``).

    with Server() as server:
        ...  # connect to 127.0.0.1:server.port

    class SomeTest(unittest.TestCase):
        def setUp(self):
            self.server = start(self)  # stopped by the test's cleanup

Every wait is bounded: a server that does not come up within ``start_timeout`` seconds is
killed and the test fails with the end of its log; one that does not stop within
``stop_timeout`` seconds of SIGINT is killed.
"""

import atexit
import os
import signal
import socket
import subprocess
import tempfile
import time

ENV = "COOPERATION_SERVER"

# Servers still running, stopped at exit if a test run is interrupted between start and stop.
_running = set()


class ServerError(RuntimeError):
    """The server could not be found, started or stopped."""


def binary():
    """The server binary named by ``COOPERATION_SERVER``."""
    path = os.environ.get(ENV)
    if not path:
        raise ServerError(
            f"{ENV} is not set: set it to the cooperation-server binary, e.g. "
            f"{ENV}=target/release/cooperation-server after "
            "`cargo build --release -p cooperation-server`"
        )
    if not os.path.isfile(path):
        raise ServerError(f"{ENV}={path!r}: no such file")
    if not os.access(path, os.X_OK):
        raise ServerError(f"{ENV}={path!r}: not executable")
    return path


def free_port():
    """A loopback port nobody listens on now (the server may still lose a race for it; `Server`
    then tries another)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


class Server:
    """One cooperation-server process.

    ``settings``: the text of a settings file (``docs/settings.md``), written to a temporary
    directory and passed with ``--settings``; ``None`` keeps the server's default
    (``config/cooperation.param.yaml``). ``args``: further command-line arguments.
    """

    host = "127.0.0.1"

    def __init__(self, settings=None, args=(), start_timeout=10.0, stop_timeout=5.0):
        self.settings = settings
        self.args = list(args)
        self.start_timeout = start_timeout
        self.stop_timeout = stop_timeout
        self.port = None
        self.process = None
        self._dir = None
        self._log = None

    # -- lifecycle ---------------------------------------------------------------------------

    def start(self):
        path = binary()
        self._dir = tempfile.TemporaryDirectory(prefix="cooperation-server-")
        command = [path]
        if self.settings is not None:
            settings = os.path.join(self._dir.name, "settings.param.yaml")
            with open(settings, "w", encoding="utf-8") as file:
                file.write(self.settings)
            command += ["--settings", settings]
        command += self.args
        try:
            # A port found free can be taken before the server binds it: then try another.
            for _attempt in range(3):
                self.port = free_port()
                if self._spawn(command + ["--listen", f"{self.host}:{self.port}"]):
                    return self
            raise ServerError(f"the server found no free port:\n{self.log_tail()}")
        except BaseException:
            self.stop()
            raise

    def _spawn(self, command):
        """Starts the process; True once it accepts connections, False if it could not bind."""
        self._close_log()
        self._log = open(os.path.join(self._dir.name, "server.log"), "w+b")
        environment = dict(os.environ)
        environment.setdefault("RUST_LOG", "info")
        environment["NO_COLOR"] = "1"
        self.process = subprocess.Popen(
            command,
            stdin=subprocess.DEVNULL,
            stdout=self._log,
            stderr=subprocess.STDOUT,
            env=environment,
        )
        _running.add(self)
        deadline = time.monotonic() + self.start_timeout
        while True:
            if self.process.poll() is not None:
                log = self.log_tail()
                self._reap()
                if "cannot listen" in log:
                    return False
                raise ServerError(
                    f"the server exited with status {self.process.returncode} before it "
                    f"accepted connections:\n{log}"
                )
            try:
                with socket.create_connection((self.host, self.port), timeout=0.2):
                    return True
            except OSError:
                pass
            if time.monotonic() > deadline:
                raise ServerError(
                    f"the server did not accept connections on {self.host}:{self.port} "
                    f"within {self.start_timeout} s:\n{self.log_tail()}"
                )
            time.sleep(0.02)

    def stop(self):
        """Stops the process: SIGINT (the server's graceful shutdown), then SIGKILL if it has not
        exited within ``stop_timeout`` seconds. Safe to call more than once."""
        process = self.process
        if process is not None and process.poll() is None:
            try:
                process.send_signal(signal.SIGINT)
                process.wait(self.stop_timeout)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait(self.stop_timeout)
        self._reap()
        self._close_log()
        if self._dir is not None:
            self._dir.cleanup()
            self._dir = None

    def _reap(self):
        _running.discard(self)

    def _close_log(self):
        if self._log is not None:
            self._log.close()
            self._log = None

    def __enter__(self):
        return self.start()

    def __exit__(self, *_exc):
        self.stop()
        return False

    # -- inspection --------------------------------------------------------------------------

    @property
    def running(self):
        return self.process is not None and self.process.poll() is None

    def log(self):
        """The server's output so far."""
        if self._log is None:
            return ""
        self._log.flush()
        self._log.seek(0)
        text = self._log.read().decode("utf-8", "replace")
        self._log.seek(0, os.SEEK_END)
        return text

    def log_tail(self, lines=20):
        return "\n".join(self.log().splitlines()[-lines:])


def start(test, **options):
    """A started `Server` that `test` (a ``unittest.TestCase``) stops in its cleanup; its clients'
    cleanups, registered later, run first."""
    server = Server(**options)
    test.addCleanup(server.stop)
    return server.start()


@atexit.register
def _stop_all():
    for server in list(_running):
        server.stop()
