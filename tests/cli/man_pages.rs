//! The committed man pages must match the argument definitions.
//! Regenerate them with `UPDATE_MAN=1 cargo test man_pages`.

use crate::util::repo;

#[test]
fn man_pages_match_the_argument_definitions() {
    let update = std::env::var_os("UPDATE_MAN").is_some();
    let mut stale = Vec::new();
    for cmd in patkit::cli::commands() {
        let name = cmd.get_name().to_string();
        let page = patkit::cli::man_page(cmd);
        let path = repo(&format!("man/{name}.1"));
        if update {
            std::fs::write(&path, &page).unwrap();
        } else if std::fs::read_to_string(&path).ok().as_deref() != Some(page.as_str()) {
            stale.push(path.display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "stale or missing man pages (run `UPDATE_MAN=1 cargo test man_pages`): {stale:?}"
    );
}

#[test]
fn every_binary_has_a_man_page_and_a_help_with_examples() {
    let names: Vec<String> = patkit::cli::commands()
        .iter()
        .map(|c| c.get_name().to_string())
        .collect();
    for entry in std::fs::read_dir(repo("src/bin")).unwrap() {
        let file = entry.unwrap().file_name().to_string_lossy().into_owned();
        let tool = file.trim_end_matches(".rs");
        assert!(
            names.iter().any(|n| n == tool),
            "{tool} is missing from cli::commands()"
        );
    }
    for cmd in patkit::cli::commands() {
        let help = cmd
            .get_after_help()
            .map(|h| h.to_string())
            .unwrap_or_default();
        assert!(
            help.contains("Examples:"),
            "{} --help has no examples",
            cmd.get_name()
        );
    }
}
