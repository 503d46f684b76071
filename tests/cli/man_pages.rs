//! The committed man pages and shell completions must match the argument
//! definitions. Regenerate them with `UPDATE_MAN=1 cargo test man_pages`.

use crate::util::repo;

#[test]
fn man_pages_match_the_argument_definitions() {
    let update = std::env::var_os("UPDATE_MAN").is_some();
    let mut stale = Vec::new();
    for cmd in patkit::cli::commands() {
        let name = cmd.get_name().to_string();
        let page = patkit::cli::man_page(cmd.clone());
        let path = repo(&format!("man/{name}.1"));
        let mut files = vec![(path, page)];
        for (shell, install) in patkit::cli::COMPLETION_SHELLS {
            let file = install.rsplit('/').next().unwrap().replace("{}", &name);
            files.push((
                repo(&format!("completions/{shell}/{file}")),
                patkit::cli::completion(cmd.clone(), shell),
            ));
        }
        for (path, text) in files {
            if update {
                std::fs::create_dir_all(path.parent().unwrap()).unwrap();
                std::fs::write(&path, &text).unwrap();
            } else if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
                stale.push(path.display().to_string());
            }
        }
    }
    assert!(
        stale.is_empty(),
        "stale or missing man pages or completions (run `UPDATE_MAN=1 cargo test man_pages`): {stale:?}"
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
