//! `rocking reference cli|tables` (hidden): the references of
//! `docs/cli.md` and `docs/tables.md`, generated from the one definition
//! of each flag (clap's command tree, stage commands included) and of each
//! table (`rocking::tables::reference`), as ripgrep generates its docs
//! from its flag definitions. Tests hold the committed files equal to
//! these.

use clap::{Arg, Command};

/// Print a generated reference (docs/cli.md or docs/tables.md).
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Which reference.
    #[arg(value_parser = ["cli", "tables"])]
    which: String,
}

pub fn run(args: Args, cli: Command) -> anyhow::Result<()> {
    let text = match args.which.as_str() {
        "cli" => cli_markdown(cli),
        _ => rocking::tables::reference::markdown(),
    };
    print!("{text}");
    Ok(())
}

/// `docs/cli.md`: every visible command, its description, usage and
/// options.
pub fn cli_markdown(mut cli: Command) -> String {
    cli.build();
    let mut s = String::from(
        "# Command-line reference\n\n\
         <!-- Generated from the command line's definitions (clap) by `rocking reference cli`;\n\
         a test holds this file to it. Rewrite it with\n\
         `ROCKING_BLESS=1 cargo test --release cli_reference`. -->\n\n\
         `rocking --help` lists the commands and `rocking <command> --help` explains one;\n\
         this page is the same text, every command on one page. The guide\n\
         (`docs/guide.md`) shows them at work.\n\n",
    );
    if let Some(about) = cli.get_long_about().or(cli.get_about()) {
        s.push_str(&format!("{}\n\n", plain(&about.to_string())));
    }
    let subs: Vec<&Command> = cli
        .get_subcommands()
        .filter(|c| !c.is_hide_set() && c.get_name() != "help")
        .collect();
    for c in &subs {
        s.push_str(&format!("- [`rocking {0}`](#rocking-{0})\n", c.get_name()));
    }
    for c in subs {
        s.push_str(&command(c));
    }
    s
}

fn command(c: &Command) -> String {
    let name = c.get_name();
    let mut s = format!("\n## `rocking {name}`\n\n");
    if let Some(about) = c.get_long_about().or(c.get_about()) {
        s.push_str(&format!("{}\n\n", plain(&about.to_string())));
    }
    let usage = c
        .clone()
        .bin_name(format!("rocking {name}"))
        .render_usage()
        .to_string();
    let usage = usage.trim_start_matches("Usage: ").trim();
    s.push_str(&format!("```text\n{usage}\n```\n\n"));
    let args: Vec<&Arg> = c
        .get_arguments()
        .filter(|a| !a.is_hide_set() && !matches!(a.get_id().as_str(), "help" | "version"))
        .collect();
    if args.is_empty() {
        return s;
    }
    s.push_str("| option | value | default | meaning |\n|---|---|---|---|\n");
    for a in args {
        s.push_str(&option(a));
    }
    s
}

fn option(a: &Arg) -> String {
    let flag = match (a.get_long(), a.get_short()) {
        (Some(l), _) => format!("`--{l}`"),
        (None, Some(c)) => format!("`-{c}`"),
        (None, None) => format!(
            "`{}`",
            a.get_value_names()
                .and_then(|v| v.first())
                .map_or(a.get_id().to_string(), |v| v.to_string())
        ),
    };
    let takes_value = a.get_num_args().is_some_and(|n| n.takes_values());
    let value = match (takes_value, a.get_long(), a.get_value_names()) {
        (false, _, _) => String::new(),
        (true, None, _) => String::new(),
        (true, Some(_), Some(names)) => format!("`{}`", names.join(" ")),
        (true, Some(l), None) => format!("`{}`", l.to_uppercase().replace('-', "_")),
    };
    let default: Vec<String> = a
        .get_default_values()
        .iter()
        .map(|v| v.to_string_lossy().into_owned())
        .collect();
    let default = if default.is_empty() || !takes_value {
        String::new()
    } else {
        format!("`{}`", default.join(","))
    };
    let mut meaning = a
        .get_long_help()
        .or(a.get_help())
        .map_or(String::new(), |h| plain(&h.to_string()).replace('\n', " "));
    if !meaning.is_empty() && !meaning.ends_with('.') {
        meaning.push('.');
    }
    if a.is_required_set() {
        meaning.push_str(" Required.");
    }
    let possible: Vec<String> = a
        .get_possible_values()
        .iter()
        .filter(|p| !p.is_hide_set())
        .map(|p| match p.get_help() {
            Some(h) => format!("`{}` ({})", p.get_name(), plain(&h.to_string())),
            None => format!("`{}`", p.get_name()),
        })
        .collect();
    if !possible.is_empty() && takes_value {
        meaning.push_str(&format!(" One of: {}.", possible.join(", ")));
    }
    format!(
        "| {flag} | {value} | {default} | {} |\n",
        meaning.trim().replace('|', "\\|")
    )
}

/// Help text as Markdown: clap's paragraphs kept, lines unwrapped.
fn plain(text: &str) -> String {
    text.split("\n\n")
        .map(|p| p.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect::<Vec<_>>()
        .join("\n\n")
}
