//! `frep serve` end to end: starts on a free port, answers, and shuts down
//! gracefully on SIGTERM with exit status 0.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::sync::mpsc;

/// A plain HTTP/1.1 GET: status line and body.
fn get(addr: &str, path: &str) -> String {
    let mut s = TcpStream::connect(addr).unwrap();
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut out = String::new();
    s.read_to_string(&mut out).unwrap();
    out
}

#[cfg(unix)]
#[test]
fn serve_answers_and_stops_on_sigterm() {
    let data = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_frep"))
        .args([
            "serve",
            "--addr",
            "127.0.0.1:0",
            "--static",
            "/nonexistent",
            "--data",
        ])
        .arg(data.path())
        .env("RUST_LOG", "info")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The log goes through a thread so that the pipe never fills.
    let stderr = child.stderr.take().unwrap();
    let (tx, rx) = mpsc::channel::<String>();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines() {
            let Ok(line) = line else { break };
            let _ = tx.send(line);
        }
    });
    let mut log = Vec::new();
    let addr = loop {
        let line = rx.recv().expect("frep serve exited before listening");
        log.push(line.clone());
        // "listening addr=127.0.0.1:PORT": the store is open, examples in.
        if let Some(rest) = line.split("listening addr=").nth(1) {
            break rest.split_whitespace().next().unwrap().to_string();
        }
    };
    let health = get(&addr, "/api/health");
    assert!(health.starts_with("HTTP/1.1 200"), "{health}");
    assert!(health.contains("\"status\":\"ok\""), "{health}");
    let models = get(&addr, "/api/models");
    assert!(models.contains("\"name\":\"sake_pot\""), "examples loaded");
    let page = get(&addr, "/");
    assert!(page.contains("<h2>sake_pot</h2>"), "the model page");

    let status = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let exit = child.wait().unwrap();
    reader.join().unwrap();
    log.extend(rx.try_iter());
    assert!(exit.success(), "exit {exit:?}; log:\n{}", log.join("\n"));
    let log = log.join("\n");
    assert!(log.contains("SIGTERM"), "{log}");
    assert!(log.contains("store closed"), "{log}");
    assert!(data.path().join("frep.sqlite").is_file());
}
