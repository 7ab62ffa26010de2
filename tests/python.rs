//! The Python package (`python/`) against the command line
//! (`ROCKING_PYPKG`: a Python with `rocking` and pytest installed; CI makes
//! one): its pytest suite (every function against the command's JSON, bit
//! for bit; errors; the GIL released; pipelines and tables), and the
//! README's two Python lines.

use std::process::Command;

use crate::util::{rocking, root, stderr};

fn python() -> Option<String> {
    match std::env::var("ROCKING_PYPKG") {
        Ok(p) => Some(p),
        Err(_) => {
            eprintln!("skipped: set ROCKING_PYPKG to a python with `pip install ./python pytest` (.ci/run does)");
            None
        }
    }
}

#[test]
fn the_python_package_gives_the_commands_numbers() {
    let Some(py) = python() else { return };
    let out = Command::new(&py)
        .args([
            "-m",
            "pytest",
            "-q",
            "-p",
            "no:cacheprovider",
            "python/tests",
        ])
        .env("ROCKING_BIN", env!("CARGO_BIN_EXE_rocking"))
        .env("ROCKING_ROOT", root())
        .current_dir(root())
        .output()
        .expect("python runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}\n{}", stderr(&out));
    assert!(text.contains(" passed"), "{text}");
    assert!(!text.contains("skipped"), "{text}");
}

/// The README's Python section: two lines, an install and a capacity; the
/// capacity is the command line's to the bit.
#[test]
fn the_readmes_python_lines_work() {
    let Some(py) = python() else { return };
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let section = readme
        .split("\n## Python\n")
        .nth(1)
        .expect("a Python section");
    let block = section
        .split("```sh\n")
        .nth(1)
        .and_then(|b| b.split("```").next())
        .expect("a code block");
    let lines: Vec<&str> = block.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 2, "{block}");
    assert_eq!(lines[0], "pip install ./python");
    let code = lines[1]
        .strip_prefix("python -c \"")
        .and_then(|l| l.strip_suffix('"'))
        .expect("python -c \"…\"");
    let out = Command::new(&py)
        .args(["-c", code])
        .current_dir(root())
        .output()
        .expect("python runs");
    assert!(out.status.success(), "{}", stderr(&out));
    let eta: f64 = String::from_utf8_lossy(&out.stdout).trim().parse().unwrap();
    let cli = rocking(
        &root(),
        &[
            "capacity",
            "--record",
            "records/fema-p695/far-field/RSN1111_KOBE_NIS000.AT2",
            "--p",
            "2",
            "--eps",
            "0.7",
            "--json",
        ],
    );
    let json: serde_json::Value = serde_json::from_slice(&cli.stdout).unwrap();
    assert_eq!(Some(eta), json["eta_c"].as_f64());
    assert!(
        section.contains(&format!("η_c = {eta}")),
        "the README states {eta}"
    );
}
