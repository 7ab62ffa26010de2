//! The notebook a pelicun user runs (`docs/notebooks/contents-to-pelicun.ipynb`),
//! executed as Jupyter would (`jupyter-execute`, nbclient) in the engines'
//! venv (`ROCKING_ENGINES`, with the Python package, OpenSeesPy, pelicun
//! and matplotlib, as `.ci/run` makes it): every cell runs, its two figures
//! are drawn, and its own check holds (the tool's component in pelicun
//! within 0.02 of the tool's probability on each floor).

use std::path::PathBuf;
use std::process::Command;

use serde_json::Value;

use crate::util::{root, tempdir};

#[test]
fn the_contents_notebook_runs() {
    let Ok(venv) = std::env::var("ROCKING_ENGINES") else {
        eprintln!("skipped: set ROCKING_ENGINES to the engines' venv with the package and nbclient (.ci/run)");
        return;
    };
    let venv = PathBuf::from(venv);
    let dir = tempdir();
    let out = dir.path().join("executed.ipynb");
    let run = Command::new(venv.join("bin/jupyter-execute"))
        .arg(format!("--output={}", out.display()))
        .arg(root().join("docs/notebooks/contents-to-pelicun.ipynb"))
        .env("ROCKING_ROOT", root())
        .env(
            "PATH",
            format!(
                "{}:{}",
                venv.join("bin").display(),
                std::env::var("PATH").unwrap_or_default()
            ),
        )
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    let nb: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let outputs: Vec<&Value> = nb["cells"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["cell_type"] == "code")
        .flat_map(|c| c["outputs"].as_array().unwrap())
        .collect();
    assert!(outputs.iter().all(|o| o["output_type"] != "error"));
    let images = outputs
        .iter()
        .filter(|o| o["data"].get("image/png").is_some())
        .count();
    assert_eq!(images, 2, "the fragility curves and the bars");
    let text: String = outputs
        .iter()
        .filter_map(|o| o["text"].as_array())
        .flatten()
        .filter_map(Value::as_str)
        .collect();
    assert!(text.contains("rocking's component in pelicun"), "{text}");
    assert!(text.contains("T1 = 0.500 s"), "{text}");
}
