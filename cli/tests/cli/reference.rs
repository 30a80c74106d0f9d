//! The reference page of the commands, `docs/commands.md`, and `holo
//! COMMAND --help` do not drift apart: every command and subcommand has a
//! section (`## \`holo convert mesh\``), each section's option list names
//! exactly the options `--help` lists (but `--help` itself), with each
//! option's default, and every section is a command that exists.

use std::collections::BTreeSet;
use std::path::Path;

use super::{holo, ok};

/// The page, as the repository holds it.
fn page() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/commands.md");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// `holo WORDS --help`.
fn help(words: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let args: Vec<&str> = words.iter().copied().chain(["--help"]).collect();
    String::from_utf8(ok(holo(&args, dir.path())).stdout).unwrap()
}

/// The lines of a `--help` section (`Commands:`, `Options:`) up to the next blank-line-separated heading.
fn help_section<'a>(text: &'a str, heading: &str) -> Vec<&'a str> {
    let mut lines = text.lines().skip_while(|l| *l != heading).skip(1);
    let mut out = Vec::new();
    for line in lines.by_ref() {
        if !line.is_empty() && !line.starts_with(' ') {
            break;
        }
        out.push(line);
    }
    out
}

/// Every command path with no subcommands of its own: `["info"]`, `["convert", "mesh"]`, …
fn commands(words: &[&str]) -> Vec<Vec<String>> {
    let text = help(words);
    let names: Vec<String> = help_section(&text, "Commands:")
        .iter()
        .filter(|l| l.starts_with("  ") && !l.starts_with("   "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_string)
        .collect();
    if names.is_empty() {
        return vec![words.iter().map(|w| w.to_string()).collect()];
    }
    names
        .iter()
        .flat_map(|name| {
            let mut path: Vec<&str> = words.to_vec();
            path.push(name);
            commands(&path)
        })
        .collect()
}

/// The long options `--help` lists (`--help` itself aside), each with its default if it has one.
fn help_options(text: &str) -> Vec<(String, Option<String>)> {
    let mut options: Vec<(String, Option<String>)> = Vec::new();
    for line in help_section(text, "Options:") {
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        if trimmed.starts_with('-') && indent <= 6 {
            let long = trimmed.split_whitespace().find(|w| w.starts_with("--")).expect("a long option");
            let long = long.trim_end_matches(',').to_string();
            if long != "--help" && long != "--version" {
                options.push((long, None));
            }
        }
        if let (Some(start), Some(last)) = (trimmed.find("[default: "), options.last_mut()) {
            let value = &trimmed[start + "[default: ".len()..];
            last.1 = Some(value[..value.find(']').unwrap_or(value.len())].to_string());
        }
    }
    options
}

/// The text of the section `## \`holo WORDS\``, up to the next `## `.
fn page_section<'a>(page: &'a str, words: &[String]) -> Option<&'a str> {
    let heading = format!("## `holo {}`\n", words.join(" "));
    let start = page.find(&heading)? + heading.len();
    let end = page[start..].find("\n## ").map_or(page.len(), |e| start + e);
    Some(&page[start..end])
}

/// The options a section's list names: every `--flag` in the code spans that
/// open a bullet, before its first `: ` outside a code span; each with the
/// bullet's whole text.
fn page_options(section: &str) -> Vec<(String, String)> {
    let mut options = Vec::new();
    for bullet in section.split("\n- ").skip(1) {
        if !bullet.starts_with('`') {
            continue;
        }
        let bullet = bullet.split("\n\n").next().unwrap_or(bullet);
        let mut in_code = false;
        let mut head_end = bullet.len();
        for (i, c) in bullet.char_indices() {
            match c {
                '`' => in_code = !in_code,
                ':' if !in_code && bullet[i..].starts_with(": ") => {
                    head_end = i;
                    break;
                }
                _ => {}
            }
        }
        for (k, span) in bullet[..head_end].split('`').enumerate() {
            if k % 2 == 1 {
                for word in span.split([' ', ',', '|']).filter(|w| w.starts_with("--")) {
                    options.push((word.to_string(), bullet.to_string()));
                }
            }
        }
    }
    options
}

#[test]
fn the_reference_page_and_help_agree_on_every_command_and_option() {
    let page = page();
    let all = commands(&[]);
    assert!(all.len() >= 20, "{all:?}");
    let mut problems = Vec::new();
    for words in &all {
        let name = format!("holo {}", words.join(" "));
        let Some(section) = page_section(&page, words) else {
            problems.push(format!("{name}: no section `## \\`{name}\\`` in docs/commands.md"));
            continue;
        };
        let args: Vec<&str> = words.iter().map(String::as_str).collect();
        let listed = help_options(&help(&args));
        let documented = page_options(section);
        let documented_names: BTreeSet<&str> = documented.iter().map(|(o, _)| o.as_str()).collect();
        let listed_names: BTreeSet<&str> = listed.iter().map(|(o, _)| o.as_str()).collect();
        for missing in listed_names.difference(&documented_names) {
            problems.push(format!("{name}: {missing} is in --help but not in its section"));
        }
        for stale in documented_names.difference(&listed_names) {
            problems.push(format!("{name}: {stale} is in its section but not in --help"));
        }
        for (option, default) in &listed {
            let (Some(default), Some((_, bullet))) = (default, documented.iter().find(|(o, _)| o == option)) else {
                continue;
            };
            if !bullet.contains(default.as_str()) {
                problems.push(format!("{name}: {option}'s default {default} is not in its section"));
            }
        }
    }
    // Every section is a command that exists.
    for heading in page.lines().filter_map(|l| l.strip_prefix("## `holo ")) {
        let words: Vec<String> = heading.trim_end_matches('`').split(' ').map(str::to_string).collect();
        if !all.contains(&words) {
            problems.push(format!("docs/commands.md: section `holo {}` is no command", words.join(" ")));
        }
    }
    assert!(problems.is_empty(), "docs/commands.md and --help disagree:\n{}", problems.join("\n"));
}

#[test]
fn the_page_s_parser_reads_what_it_must() {
    let section =
        "\nText.\n\n- `--a`, `--b N` (default `zip`), `--c`: what.\n- `-o, --output DIR`: a `--not-an-option`.\n\
                   - `--light KIND:VALUES` (repeatable): `dir:1,2,3`.\nNot a bullet `--x`.\n";
    let names: Vec<String> = page_options(section).into_iter().map(|(o, _)| o).collect();
    assert_eq!(names, ["--a", "--b", "--c", "--output", "--light"]);
    let text = "Usage: x\n\nOptions:\n      --layout <LAYOUT>\n          Display --layout.\n          \n          \
                [default: mark3]\n\n  -o, --output <OUTPUT>\n          Output\n  -h, --help\n          Print help\n";
    let listed = help_options(text);
    assert_eq!(listed, [("--layout".to_string(), Some("mark3".to_string())), ("--output".to_string(), None)]);
}
