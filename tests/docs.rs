//! The documents against the code: the generated references equal what
//! the code generates, every table and every stage appears wherever they
//! are listed, and every command the README and the guide show runs and
//! prints what they show.

use std::fs;

use crate::util::{rocking, root, stderr, stdout, tempdir};

/// `file` (from the repository root) equals `generated`; with
/// `ROCKING_BLESS=1` it is rewritten instead (review the diff).
fn generated(file: &str, generated: &str) {
    let path = root().join(file);
    if std::env::var_os("ROCKING_BLESS").is_some() {
        fs::write(&path, generated).unwrap();
        return;
    }
    let committed = fs::read_to_string(&path).unwrap_or_default();
    if committed != generated {
        let line = committed
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(committed.lines().count().min(generated.lines().count()));
        panic!(
            "{file} is not what the code generates (first difference at line {}); \
             rerun with ROCKING_BLESS=1 and review the diff",
            line + 1
        );
    }
}

#[test]
fn cli_reference_is_generated_from_the_command_line() {
    let out = rocking(&root(), &["reference", "cli"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    // Every visible command is there, the stage commands included.
    for c in [
        "simulate",
        "capacity",
        "fragility",
        "risk",
        "export",
        "run",
        "sweep",
        "report",
    ] {
        assert!(text.contains(&format!("\n## `rocking {c}`\n")), "{c}");
    }
    generated("docs/cli.md", &text);
}

#[test]
fn tables_reference_is_generated_from_the_tables() {
    generated("docs/tables.md", &rocking::tables::reference::markdown());
}

/// The catalog behind docs/tables.md lists every `table!` of src/tables
/// (and the hand-made records table), each once, each column documented.
#[test]
fn every_table_is_in_the_reference() {
    let mut defined = 0;
    for entry in fs::read_dir(root().join("src/tables")).unwrap() {
        let path = entry.unwrap().path();
        if path.file_name().is_some_and(|n| n == "table.rs") {
            continue; // the macro's own file
        }
        defined += fs::read_to_string(&path)
            .unwrap()
            .matches("table! {")
            .count();
    }
    let catalog = rocking::tables::reference::catalog();
    assert_eq!(
        catalog.len(),
        defined + 1,
        "the catalog and the table! definitions"
    );
    let mut names: Vec<&str> = catalog.iter().map(|t| t.name).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), catalog.len(), "a table listed twice");
    for t in &catalog {
        assert!(!t.doc.is_empty(), "{}: no description", t.name);
        for f in t.schema.fields() {
            let documented = t
                .columns
                .iter()
                .any(|(n, d)| n == f.name() && d.iter().any(|l| !l.trim().is_empty()));
            assert!(documented, "{}.{}: no description", t.name, f.name());
        }
    }
}

/// Every stage of the registry appears wherever stages are listed: the
/// README's and the guide's stage tables, the guide's order of a run, the
/// library's module map, the code map's row of the stages, and (for a
/// stage with a command) the command-line reference and the guide's list
/// of the stage commands.
#[test]
fn every_stage_appears_wherever_stages_are_listed() {
    use rocking::stages::STAGES;
    let readme = fs::read_to_string(root().join("README.md")).unwrap();
    let guide = fs::read_to_string(root().join("docs/guide.md")).unwrap();
    let lib = fs::read_to_string(root().join("src/lib.rs")).unwrap();
    let arch = fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let cli = fs::read_to_string(root().join("docs/cli.md")).unwrap();
    let between = |text: &str, from: &str, to: &str| -> String {
        let start = text.find(from).unwrap_or_else(|| panic!("{from}"));
        let rest = &text[start..];
        rest[..rest.find(to).unwrap_or_else(|| panic!("{to}"))].replace('\n', " ")
    };
    let order = between(&guide, "`rocking run PIPELINE.toml` runs", "Run it again");
    let commands = between(
        &guide,
        "Each stage after ingest is also a command",
        "[--outputs",
    );
    let stages_row = between(&arch, "| `src/stages/` |", "\n");
    for s in STAGES {
        let name = s.name();
        assert!(
            readme.contains(&format!("| **{name}** |")),
            "README's stage table: {name}"
        );
        assert!(
            guide.contains(&format!("| **{name}** |")),
            "the guide's stage table: {name}"
        );
        assert!(
            order.contains(&format!(" {name}")),
            "the guide's order of a run: {name}"
        );
        assert!(
            stages_row.contains(&format!("`{name}`")),
            "ARCHITECTURE.md's row of src/stages/: {name}"
        );
        assert!(
            lib.contains(&format!("**{name}**")),
            "src/lib.rs's stages: {name}"
        );
        assert!(
            arch.contains(&format!("`{name}`")),
            "ARCHITECTURE.md: {name}"
        );
        if s.has_command() {
            assert!(
                cli.contains(&format!("## `rocking {name}`")),
                "docs/cli.md: {name}"
            );
            assert!(
                commands.contains(&format!("{name}|")) || commands.contains(&format!("|{name} ")),
                "the guide's stage commands: {name}"
            );
        }
    }
}

/// A scratch folder with the repository's records and pipelines in it, for
/// the documents' commands (their outputs go under its `outputs/`).
fn scratch() -> crate::util::TempDir {
    let dir = tempdir();
    for sub in ["records", "pipelines"] {
        std::os::unix::fs::symlink(root().join(sub), dir.path().join(sub)).unwrap();
    }
    dir
}

/// The commands of a Markdown document: every `sh` block's lines (each a
/// `cargo run --release -- …` command), with the `text` block that follows
/// a one-command block, if one does.
fn commands(doc: &str) -> Vec<(String, Option<String>)> {
    let mut out = Vec::new();
    let mut rest = doc;
    while let Some(at) = rest.find("```sh\n") {
        rest = &rest[at + 6..];
        let end = rest.find("```").expect("a closed block");
        let lines: Vec<String> = rest[..end]
            .lines()
            .filter(|l| !l.trim().is_empty())
            .map(String::from)
            .collect();
        rest = &rest[end + 3..];
        let shown = rest
            .strip_prefix("\n\n```text\n")
            .map(|r| r[..r.find("```").expect("a closed block")].to_string());
        let n = lines.len();
        for (k, line) in lines.into_iter().enumerate() {
            out.push((line, shown.clone().filter(|_| n == 1 && k == 0)));
        }
    }
    out
}

/// Runs a document's commands in order, in one scratch folder, and checks
/// each shown output: exactly, or its beginning where the shown text ends
/// with a line `  …`.
fn run_document(file: &str) -> usize {
    let doc = fs::read_to_string(root().join(file)).unwrap();
    let dir = scratch();
    let all = commands(&doc);
    for (line, shown) in &all {
        let Some(args) = line.strip_prefix("cargo run --release -- ") else {
            // Not the tool (the test command, pip): shown, not run here.
            continue;
        };
        let args: Vec<&str> = args.split_whitespace().collect();
        let out = rocking(dir.path(), &args);
        assert!(
            out.status.success(),
            "{file}: `{line}` failed: {}",
            stderr(&out)
        );
        let Some(shown) = shown else { continue };
        let printed = stdout(&out);
        match shown.strip_suffix("  …\n") {
            Some(start) => assert!(
                printed.starts_with(start),
                "{file}: update the output shown for `{line}`:\n{printed}"
            ),
            None => assert_eq!(
                &printed, shown,
                "{file}: update the output shown for `{line}`"
            ),
        }
    }
    all.len()
}

#[test]
fn the_readmes_commands_print_what_it_shows() {
    assert!(run_document("README.md") >= 3);
}

#[test]
fn the_guides_recipes_print_what_it_shows() {
    assert!(run_document("docs/guide.md") >= 10);
}

/// The reader of `sh` and `text` blocks, on a document of its own.
#[test]
fn documents_commands_are_read_with_their_outputs() {
    let doc = "x\n```sh\ncargo run --release -- a b\n```\n\n```text\nout\n```\n\
               ```sh\ncargo run --release -- c\ncargo run --release -- d\n```\n\n```text\nno\n```\n";
    let got = commands(doc);
    assert_eq!(
        got,
        vec![
            (
                "cargo run --release -- a b".to_string(),
                Some("out\n".to_string())
            ),
            ("cargo run --release -- c".to_string(), None),
            ("cargo run --release -- d".to_string(), None),
        ]
    );
}

/// The key reference of pipelines/README.md, copied as it is into a
/// pipeline file beside the bundled ones, is a pipeline the tool accepts
/// (it set the linearised model beside the nonlinear model's integrator,
/// which is refused, and named its study `quick`).
#[test]
fn the_pipelines_key_reference_is_a_pipeline() {
    let readme = fs::read_to_string(root().join("pipelines/README.md")).unwrap();
    let block = readme
        .split("```toml\n")
        .nth(1)
        .and_then(|b| b.split("\n```").next())
        .expect("pipelines/README.md has a ```toml block");
    let dir = tempdir();
    let pipelines = dir.path().join("pipelines");
    fs::create_dir_all(&pipelines).unwrap();
    // Its relative paths are the bundled pipelines' (../records).
    std::os::unix::fs::symlink(root().join("records"), dir.path().join("records")).unwrap();
    let file = pipelines.join("keys.toml");
    fs::write(&file, block).unwrap();
    let out = rocking(dir.path(), &["status", file.to_str().unwrap()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.starts_with("outputs of `my-study`"), "{text}");
}
