//! `holo layout`: a layout as a profile, the start of a custom one; and the
//! list of built-in layouts.

use std::process::ExitCode;

use clap::Args;
use holo::layout::{Basis, Layout, BUILTIN};
use serde::Serialize;

use super::Outcome;
use crate::args::{layout_help, load_layout};
use crate::out::{json, put, say};

/// Print a layout profile (TOML, or JSON with --json): the numbers a
/// layout uses, and a starting point for a custom profile. With --list,
/// every built-in layout and its parallax.
#[derive(Args)]
pub struct LayoutArgs {
    #[arg(help = layout_help(""), required_unless_present = "list", conflicts_with = "list")]
    name: Option<String>,
    /// List the built-in layouts (name, parallax, emitters, views, basis,
    /// description) instead of printing one.
    #[arg(long)]
    list: bool,
    /// Print JSON instead of TOML (with --list: an array, one object per
    /// layout).
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    blanking: crate::args::BlankingArg,
}

pub fn run(a: LayoutArgs) -> Outcome {
    let Some(name) = a.name else { return list(a.json) };
    let layout = a.blanking.apply(load_layout(&name)?);
    if a.json {
        json(&layout)?;
    } else {
        put!("{}", layout.to_toml());
    }
    Ok(ExitCode::SUCCESS)
}

/// One built-in layout, as `--list` says it.
#[derive(Serialize)]
struct Listed {
    name: &'static str,
    /// "horizontal" or "full".
    parallax: &'static str,
    emitters: usize,
    /// Emitter rows: hololines, for horizontal parallax.
    rows: usize,
    views: usize,
    /// Vertical views (full parallax only).
    #[serde(skip_serializing_if = "Option::is_none")]
    vertical_views: Option<usize>,
    /// The fringe basis ("chirp", "hogel"), or none for a geometry only.
    basis: Option<&'static str>,
    description: String,
}

impl Listed {
    fn of(name: &'static str, layout: &Layout) -> Listed {
        let g = &layout.geometry;
        Listed {
            name,
            parallax: if g.vertical_views.is_some() { "full" } else { "horizontal" },
            emitters: g.emitters,
            rows: g.hololines,
            views: g.views.count,
            vertical_views: g.vertical_views.as_ref().map(|v| v.count),
            basis: layout.fringe.as_ref().map(|f| match f.basis {
                Basis::Chirp { .. } => "chirp",
                Basis::Hogel { .. } => "hogel",
            }),
            description: layout.description.clone(),
        }
    }
}

fn list(as_json: bool) -> Outcome {
    let listed: Vec<Listed> = BUILTIN
        .into_iter()
        .map(|name| Listed::of(name, &holo::layout::builtin(name).expect("every name in BUILTIN is built in")))
        .collect();
    if as_json {
        json(&listed)?;
        return Ok(ExitCode::SUCCESS);
    }
    let views = |l: &Listed| match l.vertical_views {
        Some(k) => format!("{} × {k}", l.views),
        None => l.views.to_string(),
    };
    let width = listed.iter().map(|l| l.name.len()).max().unwrap_or(0);
    say!("{:width$}  {:10}  {:>11}  {:>7}  {:6}  description", "name", "parallax", "emitters", "views", "basis");
    for l in &listed {
        say!(
            "{:width$}  {:10}  {:>11}  {:>7}  {:6}  {}",
            l.name,
            l.parallax,
            format!("{} × {}", l.emitters, l.rows),
            views(l),
            l.basis.unwrap_or("none"),
            l.description
        );
    }
    Ok(ExitCode::SUCCESS)
}
