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
