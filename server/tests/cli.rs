//! The command line: a node that cannot start says why and exits with status 1, in a log
//! with no colour codes when it is not written to a terminal (`docs/server.md`).

use std::process::Command;

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
    std::fs::remove_dir_all(&dir).expect("removed");
}
