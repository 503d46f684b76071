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

/// The section-5 pages: the file formats, each made from its `docs/` page
/// (as netpbm documents pbm(5)), with its name and one-line description.
/// `make install` installs every file of `man/man5/`.
pub const FORMAT_PAGES: [(&str, &str, &str); 5] = [
    (
        "docs/pat-format.md",
        "pat",
        "the .pat multi-colour texture pattern file",
    ),
    (
        "docs/stream-format.md",
        "patkit-stream",
        "the polygon stream of patkit's tools (JSON or NDJSON records)",
    ),
    (
        "docs/camera.md",
        "patkit-camera",
        "the camera file of scene-render and polyfill3",
    ),
    (
        "docs/stripe-files.md",
        "patkit-stripe",
        "stripe texture files: modulation maps, translation maps, colour-code tables",
    ),
    (
        "docs/json.md",
        "patkit-json",
        "the --json reports of pat-info, polyfill3 and scene-render",
    ),
];

#[test]
fn format_man_pages_match_their_docs_pages() {
    let update = std::env::var_os("UPDATE_MAN").is_some();
    let mut stale = Vec::new();
    let mut made = Vec::new();
    let names: Vec<&str> = FORMAT_PAGES.iter().map(|p| p.1).collect();
    assert_eq!(
        names,
        patkit::cli::FORMAT_PAGES,
        "the pages every SEE ALSO names"
    );
    for (doc, name, what) in FORMAT_PAGES {
        let text = std::fs::read_to_string(repo(doc)).unwrap();
        let page = markdown_to_man(&text, name, what);
        let path = repo(&format!("man/man5/{name}.5"));
        made.push(format!("{name}.5"));
        if update {
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, &page).unwrap();
        } else if std::fs::read_to_string(&path).ok().as_deref() != Some(page.as_str()) {
            stale.push(path.display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "stale or missing section-5 man pages (run `UPDATE_MAN=1 cargo test man_pages`): {stale:?}"
    );
    // No page left over from a removed format: make install copies them all.
    let mut present: Vec<String> = std::fs::read_dir(repo("man/man5"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    present.sort();
    made.sort();
    assert_eq!(present, made, "man/man5 holds exactly the format pages");
}

/// Text for roff: backslashes and a leading `.` or `'` escaped, and
/// Markdown's inline marks (`code`, **bold**, *italic*, [links](x)) turned
/// into fonts.
fn roff_inline(s: &str) -> String {
    let mut out = String::new();
    let chars: Vec<char> = s.chars().collect();
    let mut i = 0;
    let mut bold = false;
    let mut italic = false;
    while i < chars.len() {
        let c = chars[i];
        let rest: String = chars[i..].iter().collect();
        if c == '`' {
            if let Some(end) = rest[1..].find('`') {
                let code: String = rest[1..1 + end].to_string();
                out.push_str(&format!("\\fB{}\\fR", roff_escape(&code)));
                i += code.chars().count() + 2;
                continue;
            }
        }
        if rest.starts_with("**") {
            bold = !bold;
            out.push_str(if bold { "\\fB" } else { "\\fR" });
            i += 2;
            continue;
        }
        if c == '*' && (italic || chars.get(i + 1).is_some_and(|n| !n.is_whitespace())) {
            italic = !italic;
            out.push_str(if italic { "\\fI" } else { "\\fR" });
            i += 1;
            continue;
        }
        if c == '[' {
            if let Some(close) = rest.find("](") {
                if let Some(end) = rest[close..].find(')') {
                    let label = &rest[1..close];
                    out.push_str(&roff_inline(label));
                    i += rest[..close + end + 1].chars().count();
                    continue;
                }
            }
        }
        out.push_str(&roff_escape(&c.to_string()));
        i += 1;
    }
    out
}

/// Backslashes and hyphens for roff (a `-` in roff is a hyphen, `\-` the
/// minus that options are written with).
fn roff_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\e"),
            '-' => out.push_str("\\-"),
            // groff reads its input as Latin-1 unless told otherwise: other
            // characters go as their Unicode names, which every output device knows.
            c if !c.is_ascii() => out.push_str(&format!("\\[u{:04X}]", c as u32)),
            c => out.push(c),
        }
    }
    out
}

/// A line that roff would read as a request when it starts with `.` or `'`.
fn roff_line(s: &str) -> String {
    if s.starts_with('.') || s.starts_with('\'') {
        format!("\\&{s}")
    } else {
        s.to_string()
    }
}

/// The Markdown of a `docs/` page as a section-5 man page: `#` is the title
/// (the NAME line replaces it), `##` sections, `###` subsections, fenced and
/// indented blocks verbatim, `- ` items as bullets, tables as tagged
/// paragraphs (the first cell the tag, the other cells under it, each after
/// its column's heading from the third on).
pub fn markdown_to_man(md: &str, name: &str, what: &str) -> String {
    let mut out = format!(
        ".TH {} 5 \"\" \"patkit\" \"File Formats\"\n.SH NAME\n{} \\- {}\n",
        name.to_uppercase(),
        roff_escape(name),
        roff_escape(what)
    );
    let mut para: Vec<String> = Vec::new();
    let mut in_code = false;
    let mut table_head: Option<Vec<String>> = None;
    let flush = |para: &mut Vec<String>, out: &mut String| {
        if para.is_empty() {
            return;
        }
        let text = para.join(" ");
        para.clear();
        if let Some(item) = text.strip_prefix("- ") {
            out.push_str(".IP \\(bu 2\n");
            out.push_str(&roff_line(&roff_inline(item)));
        } else {
            out.push_str(".PP\n");
            out.push_str(&roff_line(&roff_inline(&text)));
        }
        out.push('\n');
    };
    let mut lines = md.lines().peekable();
    while let Some(line) = lines.next() {
        if line.trim_start().starts_with("```") {
            flush(&mut para, &mut out);
            in_code = !in_code;
            out.push_str(if in_code {
                ".PP\n.RS 4\n.nf\n"
            } else {
                ".fi\n.RE\n"
            });
            continue;
        }
        if in_code {
            out.push_str(&roff_line(&roff_escape(line)));
            out.push('\n');
            continue;
        }
        if line.starts_with("    ") && para.is_empty() && !line.trim().is_empty() {
            out.push_str(".PP\n.RS 4\n.nf\n");
            let mut l = Some(line);
            while let Some(code) = l {
                out.push_str(&roff_line(&roff_escape(&code[4.min(code.len())..])));
                out.push('\n');
                l = lines.next_if(|n| n.starts_with("    ") || n.trim().is_empty());
            }
            out.push_str(".fi\n.RE\n");
            continue;
        }
        if let Some(row) = line.trim().strip_prefix('|') {
            flush(&mut para, &mut out);
            if row.chars().all(|ch| matches!(ch, '-' | ':' | '|' | ' ')) {
                continue;
            }
            let cells: Vec<String> = row
                .trim_end_matches('|')
                .split(" | ")
                .map(|c| c.trim().trim_matches('|').trim().replace("\\|", "|"))
                .collect();
            if cells
                .iter()
                .all(|c| c.chars().all(|ch| ch == '-' || ch == ':'))
            {
                continue;
            }
            match &table_head {
                None => table_head = Some(cells),
                Some(head) => {
                    out.push_str(&format!(".TP\n{}\n", roff_line(&roff_inline(&cells[0]))));
                    for (k, c) in cells.iter().enumerate().skip(1) {
                        if k > 1 {
                            out.push_str(".br\n");
                        }
                        let c = if k > 1 {
                            format!("{}: {c}", head.get(k).map_or("", String::as_str))
                        } else {
                            c.clone()
                        };
                        out.push_str(&roff_line(&roff_inline(&c)));
                        out.push('\n');
                    }
                }
            }
            continue;
        }
        table_head = None;
        if line.starts_with("# ") {
            continue;
        }
        if let Some(h) = line.strip_prefix("## ") {
            flush(&mut para, &mut out);
            out.push_str(&format!(".SH {}\n", roff_inline(&h.to_uppercase())));
            continue;
        }
        if let Some(h) = line.strip_prefix("### ") {
            flush(&mut para, &mut out);
            out.push_str(&format!(".SS {}\n", roff_inline(h)));
            continue;
        }
        if line.trim().is_empty() {
            flush(&mut para, &mut out);
            continue;
        }
        if line.starts_with("- ") {
            flush(&mut para, &mut out);
        }
        para.push(line.trim().to_string());
    }
    flush(&mut para, &mut out);
    out
}

/// Whether `text` names the project's original contract: the word SPEC (not
/// inside a word such as PERSPECTIVE) or a path out of the repository into
/// `../shared`, which an installed tool's user does not have.
fn cites_outside(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    for (i, _) in text.match_indices("SPEC") {
        let before = i.checked_sub(1).map(|j| bytes[j]);
        let after = bytes.get(i + 4).copied();
        let word = |b: Option<u8>| b.is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_');
        if !word(before) && !word(after) {
            let line = text[..i].lines().count().max(1);
            return Some(format!("line {line}: SPEC"));
        }
    }
    text.find("../shared")
        .map(|i| format!("line {}: ../shared", text[..i].lines().count().max(1)))
}

#[test]
fn no_help_man_page_or_doc_cites_a_file_outside_the_repository() {
    let mut texts: Vec<(String, String)> = Vec::new();
    for mut cmd in patkit::cli::commands() {
        let name = cmd.get_name().to_string();
        texts.push((format!("{name} --help"), cmd.render_long_help().to_string()));
    }
    let mut files = vec![repo("README.md")];
    for dir in [
        "docs",
        "man",
        "man/man5",
        "completions/bash",
        "completions/zsh",
        "completions/fish",
    ] {
        for e in std::fs::read_dir(repo(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.is_file()
                && p.extension().is_none_or(|x| x != "png")
                && p.extension().is_none_or(|x| x != "sh")
            {
                files.push(p);
            }
        }
    }
    for p in files {
        texts.push((
            p.display().to_string(),
            std::fs::read_to_string(&p).unwrap(),
        ));
    }
    let cited: Vec<String> = texts
        .iter()
        .filter_map(|(what, text)| cites_outside(text).map(|c| format!("{what}: {c}")))
        .collect();
    assert!(
        cited.is_empty(),
        "cite the project's own pages instead: {cited:?}"
    );
    assert_eq!(cites_outside("PERSPECTIVE and INSPECT"), None);
    assert!(cites_outside("see SPEC §2").is_some());
}
