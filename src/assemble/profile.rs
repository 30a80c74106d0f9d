//! Whether a display profile can be assembled: a layout is data
//! ([`crate::layout`]); that its fringe side's basis fits its geometry at
//! every colour's wavelength is checked here, against the physics of the
//! basis ([`ColourBasis::new`]).

use super::ColourBasis;
use crate::error::Result;
use crate::layout::{ColourSignals, Layout};

/// A built-in layout's name, or a path to a `.toml` or `.json` profile,
/// ready to assemble: a profile file is refused, naming the file, with every
/// reason of [`problems`].
pub fn load_layout(name_or_path: &str) -> Result<Layout> {
    Layout::load_checked(name_or_path, problems)
}

/// Everything that keeps `layout` from being assembled: its own problems
/// ([`Layout::problems`]) and, when its geometry is consistent, a fringe
/// side whose basis does not fit the geometry (at every colour's
/// wavelength), or colours summed into one signal whose bands overlap.
/// Empty for a layout without a fringe side and a consistent geometry.
pub fn problems(layout: &Layout) -> Vec<String> {
    let g = &layout.geometry;
    let p = g.problems();
    let Some(f) = &layout.fringe else { return p };
    if !p.is_empty() {
        return p;
    }
    let mut p = Vec::new();
    let mut bands = Vec::new();
    for c in 0..g.channels.len() {
        match ColourBasis::new(layout, c) {
            Ok(basis) => bands.push((c, (0..basis.zones()).map(|z| basis.signal_band(z)).collect::<Vec<_>>())),
            Err(problems) => {
                for problem in problems {
                    if !p.contains(&problem) {
                        p.push(problem);
                    }
                }
            }
        }
    }
    if f.colours == ColourSignals::Summed {
        // Each wavelength reads its own band: the bands must not overlap.
        for (i, (a, za)) in bands.iter().enumerate() {
            for (b, zb) in &bands[i + 1..] {
                for (zone, (x, y)) in za.iter().zip(zb).enumerate() {
                    if x.0 < y.1 && y.0 < x.1 {
                        p.push(format!(
                            "colours {} and {} are summed into one signal but their bands overlap in zone {} \
                             ({:.4}..{:.4} and {:.4}..{:.4} cycles per sample)",
                            g.channels[*a].name,
                            g.channels[*b].name,
                            zone + 1,
                            x.0,
                            x.1,
                            y.0,
                            y.1
                        ));
                    }
                }
            }
        }
    }
    p.extend(layout.fringe_problems());
    p
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::mark3;

    #[test]
    fn a_profile_whose_basis_does_not_fit_loads_as_data_but_not_for_assembly() {
        let dir = tempfile::tempdir().unwrap();
        let mut l = mark3();
        l.geometry.emitters = 338;
        l.fringe.as_mut().unwrap().frame_buffer.height = 2000;
        let path = dir.path().join("wide.toml");
        std::fs::write(&path, l.to_toml()).unwrap();
        let name = path.to_str().unwrap();
        // As data, only the frame buffer is wrong.
        let err = Layout::load(name).unwrap_err().to_string();
        assert!(err.contains("wide.toml") && err.contains("2640 rows") && !err.contains("338 emitters"), "{err}");
        // For assembly, every reason, the basis's first, as one sentence naming the file.
        let err = load_layout(name).unwrap_err().to_string();
        assert!(err.contains("wide.toml: inconsistent layout: "), "{err}");
        let (basis, rows) = (err.find("338 emitters do not fit").unwrap(), err.find("2640 rows").unwrap());
        assert!(basis < rows, "{err}");
        // Without the frame buffer problem, data loads and assembly still refuses.
        l.fringe.as_mut().unwrap().frame_buffer.height = mark3().fringe.unwrap().frame_buffer.height;
        std::fs::write(&path, l.to_toml()).unwrap();
        assert_eq!(Layout::load(name).unwrap(), l);
        assert!(load_layout(name).unwrap_err().to_string().contains("338 emitters do not fit"));
        assert!(crate::assemble::Assembler::new(&l).unwrap_err().to_string().contains("338 emitters do not fit"));
        assert_eq!(load_layout("mark3").unwrap(), mark3());
    }

    #[test]
    fn hostile_counts_are_refused_at_once() {
        // Counts a profile file may hold that no display has: refused with
        // their reason, without walking billions of zones or samples first
        // (before, each of these ran for hours).
        let mut zones = mark3();
        if let crate::layout::Basis::Chirp { zones, .. } = &mut zones.fringe.as_mut().unwrap().basis {
            *zones = 1 << 32;
        }
        let mut samples = mark3();
        samples.fringe.as_mut().unwrap().samples_per_hololine = 1_000_000_000_000;
        let mut reach = mark3();
        let gains = reach.fringe.as_mut().unwrap().blanking_gains.as_mut().unwrap();
        gains.flat_field.as_mut().unwrap().samples_each_side = 1 << 63;
        for (l, want) in [
            (zones, "4294967296 zone(s) × 32 views"),
            (samples, "hololine of 1000000000000 samples"),
            (reach, "samples_each_side = 9223372036854775808 is more than a hololine's 24576 samples"),
        ] {
            let p = problems(&l).join("; ");
            assert!(p.contains(want), "{p}");
        }
    }
}
