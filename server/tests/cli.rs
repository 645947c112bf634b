//! The command line: a node that cannot start says why and exits with status 1, in a log
//! with no colour codes when it is not written to a terminal (`docs/server.md`).

use std::process::Command;

/// Sets a file's permission bits.
fn set_mode(path: &std::path::Path, mode: u32) {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).expect("a mode");
}

fn refused(args: &[&str], names: &str) {
    let output = Command::new(env!("CARGO_BIN_EXE_cooperation-server"))
        .args(args)
        .env("RUST_LOG", "info")
        .output()
        .expect("the binary runs");
    assert_eq!(output.status.code(), Some(1), "{args:?}: {output:?}");
    let log = String::from_utf8_lossy(&output.stderr);
    assert!(
        log.contains(names),
        "{args:?}: {log:?} does not name {names:?}"
    );
    // Written to a pipe, not a terminal: plain text, no colour codes.
    assert!(!log.contains('\u{1b}'), "{args:?}: colour codes in {log:?}");
}

#[test]
fn a_node_that_cannot_start_says_why() {
    let dir = std::env::temp_dir().join(format!("cooperation-server-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let missing = dir.join("missing.yaml");
    refused(
        &[
            "--listen",
            "127.0.0.1:0",
            "--settings",
            missing.to_str().expect("UTF-8"),
        ],
        "missing.yaml",
    );
    let bad = dir.join("bad.yaml");
    std::fs::write(&bad, "cooperation: [").expect("written");
    refused(
        &[
            "--listen",
            "127.0.0.1:0",
            "--settings",
            bad.to_str().expect("UTF-8"),
        ],
        "bad.yaml",
    );
    refused(&["--listen", "127.0.0.1:0", "--rate", "0"], "--rate 0");
    // A host name is an address too: the node gets as far as its other options.
    refused(&["--listen", "localhost:0", "--rate", "0"], "--rate 0");
    refused(
        &["--listen", "127.0.0.1:0", "--rate", "1e-20"],
        "--rate 0.00000000000000000001",
    );
    refused(
        &["--listen", "127.0.0.1:0", "--max-clients", "0"],
        "0 clients: give from 1 to",
    );
    // An address already taken.
    let taken = std::net::TcpListener::bind("127.0.0.1:0").expect("a port");
    let address = taken.local_addr().expect("its address").to_string();
    refused(&["--listen", &address], "cannot listen on");
    // Reachable from other hosts with no credentials: not unless told.
    refused(
        &["--listen", "0.0.0.0:0"],
        "give --credentials FILE, or --anonymous",
    );
    refused(
        &["--listen", "0.0.0.0:0", "--anonymous", "--max-clients", "0"],
        "0 clients: give from 1 to",
    );
    let credentials = dir.join("credentials");
    std::fs::write(&credentials, "# the operator\noperator panel short\n").expect("written");
    // A credentials file others may read is refused before it is read.
    set_mode(&credentials, 0o644);
    let path = credentials.to_str().expect("UTF-8");
    refused(
        &["--listen", "0.0.0.0:0", "--credentials", path],
        "its mode is 644, so others than its owner may read or change its tokens; give it mode 600",
    );
    set_mode(&credentials, 0o640);
    refused(
        &["--listen", "0.0.0.0:0", "--credentials", path],
        "its mode is 640",
    );
    set_mode(&credentials, 0o600);
    refused(
        &["--listen", "0.0.0.0:0", "--credentials", path],
        "credentials: line 2: the token of \"panel\" must have at least 24 characters",
    );
    // The documentation's example tokens are refused: anyone can read them.
    std::fs::write(
        &credentials,
        "operator panel 9hX2c4mQwZr7Lk0TtB5yNvE1aPu8sDfG\n",
    )
    .expect("written");
    refused(
        &["--listen", "0.0.0.0:0", "--credentials", path],
        "an example from the documentation",
    );
    refused(
        &[
            "--listen",
            "127.0.0.1:0",
            "--credentials",
            "/nonexistent/credentials",
        ],
        "/nonexistent/credentials",
    );
    std::fs::remove_dir_all(&dir).expect("removed");
}

/// A module's credential may name an interface the settings add (`docs/settings.md`,
/// *Interfaces*), and only then.
#[test]
fn a_credential_may_name_an_interface_the_settings_add() {
    let dir = std::env::temp_dir().join(format!("cooperation-server-added-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let settings = dir.join("settings.yaml");
    std::fs::write(
        &settings,
        "/**:\n  ros__parameters:\n    cooperation:\n      policies:\n        \
         dynamic-avoidance: optional\n      interfaces:\n        dynamic_obstacle_avoidance: \
         {behavior: dynamic-avoidance, kind: steering}\n",
    )
    .expect("written");
    let credentials = dir.join("credentials");
    std::fs::write(
        &credentials,
        "module planner module-token-0123456789abcdefgh dynamic_obstacle_avoidance\n",
    )
    .expect("written");
    set_mode(&credentials, 0o600);
    let credentials = credentials.to_str().expect("UTF-8");
    // The standard interfaces alone: the credential names none of them.
    refused(
        &["--listen", "127.0.0.1:0", "--credentials", credentials],
        "dynamic_obstacle_avoidance",
    );
    // With the settings, the credentials read: the node gets as far as its address, taken.
    let taken = std::net::TcpListener::bind("127.0.0.1:0").expect("a port");
    let address = taken.local_addr().expect("its address").to_string();
    let settings = settings.to_str().expect("UTF-8");
    refused(
        &[
            "--listen",
            &address,
            "--settings",
            settings,
            "--credentials",
            credentials,
        ],
        "cannot listen on",
    );
    std::fs::remove_dir_all(&dir).expect("removed");
}

/// The node needs no file from the tree it was built in: its default settings are built in,
/// and its help names no path of the build.
#[test]
fn the_default_settings_are_built_in() {
    let output = Command::new(env!("CARGO_BIN_EXE_cooperation-server"))
        .arg("--help")
        .output()
        .expect("the binary runs");
    let help = String::from_utf8_lossy(&output.stdout);
    assert!(help.contains("--settings"), "{help}");
    assert!(!help.contains(env!("CARGO_MANIFEST_DIR")), "{help}");
    // Started from elsewhere, with no --settings, it reads its settings and gets as far as
    // its other options.
    let output = Command::new(env!("CARGO_BIN_EXE_cooperation-server"))
        .args(["--listen", "127.0.0.1:0", "--max-clients", "0"])
        .current_dir(std::env::temp_dir())
        .output()
        .expect("the binary runs");
    let log = String::from_utf8_lossy(&output.stderr);
    assert!(log.contains("0 clients: give from 1 to"), "{log}");
}

/// SIGHUP reads the credentials file again: a credential dropped from it is revoked (its
/// connection closed, its token refused) and a new one let in; a file that does not read is
/// logged and leaves the credentials in force.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sighup_reloads_the_credentials_file() {
    use crate::common::Client;
    use std::io::Read;
    const FIRST: &str = "first-operator-token-0123456789ab";
    const SECOND: &str = "second-operator-token-0123456789";
    let dir = std::env::temp_dir().join(format!("cooperation-server-hup-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let file = dir.join("credentials");
    let write = |text: String, mode: u32| {
        std::fs::write(&file, text).expect("written");
        set_mode(&file, mode);
    };
    write(format!("operator first {FIRST}\n"), 0o600);
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|probe| probe.local_addr())
        .expect("a free port")
        .port();
    let mut node = Command::new(env!("CARGO_BIN_EXE_cooperation-server"))
        .args(["--listen", &format!("127.0.0.1:{port}"), "--credentials"])
        .arg(&file)
        .env("RUST_LOG", "info")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let url = format!("ws://127.0.0.1:{port}/");
    let hangup = |node: &std::process::Child| {
        let sent = Command::new("kill")
            .args(["-HUP", &node.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(sent.success());
    };
    let mut first = None;
    for _ in 0..100 {
        if tokio::net::TcpStream::connect(("127.0.0.1", port))
            .await
            .is_ok()
        {
            first = Client::connect_as(&url, Some(FIRST)).await.ok();
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(50)).await;
    }
    let mut first = first.expect("the first operator in");
    write(format!("operator second {SECOND}\n"), 0o600);
    hangup(&node);
    let ended = tokio::time::timeout(std::time::Duration::from_secs(5), async {
        while first.next().await.is_some() {}
    })
    .await;
    assert!(
        ended.is_ok(),
        "the revoked credential's connection stays open"
    );
    assert_eq!(Client::connect_as(&url, Some(FIRST)).await.err(), Some(401));
    assert!(Client::connect_as(&url, Some(SECOND)).await.is_ok());
    // A file others may read does not read: the node says so and goes on as it was.
    write(format!("operator third {FIRST}\n"), 0o644);
    hangup(&node);
    tokio::time::sleep(std::time::Duration::from_millis(300)).await;
    assert!(Client::connect_as(&url, Some(SECOND)).await.is_ok());
    assert_eq!(Client::connect_as(&url, Some(FIRST)).await.err(), Some(401));
    node.kill().expect("stopped");
    let mut log = String::new();
    node.stderr
        .take()
        .expect("its log")
        .read_to_string(&mut log)
        .expect("read");
    let _ = node.wait();
    std::fs::remove_dir_all(&dir).expect("removed");
    assert!(log.contains("credentials reloaded"), "{log}");
    assert!(log.contains("revoked=first"), "{log}");
    assert!(
        log.contains("SIGHUP: the credentials file does not read"),
        "{log}"
    );
}
