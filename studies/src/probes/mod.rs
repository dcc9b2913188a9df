//! The measurements behind numbers the module docs and `docs/` state
//! (investigation probes, once `examples/`): `platefield study probes` writes
//! `results/probes.md` and prints the engine's timings (never written).
//!
//! | section | module | the docs citing it |
//! |---|---|---|
//! | the saddle's margin cap against a translation harmonic 2 | `saddle_cap` | `platefield::synth` ("Why a second harmonic does not lift the margin's cap"), `docs/design.md` |
//! | the in-plane harmonic-2 ratchet on squeeze_trans | `transport` | `platefield::synth::transport` |
//! | the model check (moving parts against the prediction) over the measured window | `lag_window` | `platefield::play::measure`, `platefield::play::lag`, `results/synthesis.md` |
//! | the saddle's synthesized motion point by point | `saddle_parts` | `results/synthesis.md` ("valid / judged"), `docs/design.md` |
//! | single fields' CPU time and bitwise equality on 1 and 2 threads | `engine` | `platefield::dynamics` (swing), `docs/design.md`, `docs/dev/forward-model.md` |

use std::fmt::Write as _;
use std::path::Path;

use platefield::error::Result;
use platefield::field::Grid;
use platefield::output::write_atomic;
use platefield::synth::Synthesis;

pub(crate) mod engine;
pub(crate) mod lag_window;
pub(crate) mod saddle_cap;
pub(crate) mod saddle_parts;
pub(crate) mod transport;

/// Default output folder.
pub const DIR: &str = "results";

/// Where the sequenced schedules the probes start from cache their basis.
const CACHE: &str = ".platefield-cache";

/// The default ±4 cm region with n × n points.
pub(crate) fn square(n: usize) -> Grid {
    Grid {
        n: [n, n],
        ..Grid::DEFAULT
    }
}

/// A synthesis in one line without its run time (the probes write no
/// timings; [`Synthesis::summary`] has it): its realised strength and
/// shape on the full grid, the closed-form seed's predicted and coarse
/// realised strength, the least normal force, and its notes.
pub(crate) fn synthesis_line(s: &Synthesis) -> String {
    let pct = platefield::output::percent;
    let mut line = format!(
        "synthesized ŝ {:.4} s⁻¹ at shape {} on the full grid after {} evaluations (the seed: {:.4} predicted, {:.4} realised at {} on the coarse grid); least N {:.2} m/s²",
        s.checked.realised.strength,
        pct(s.checked.realised.shape_error, 2),
        s.evaluations,
        s.seed_strength,
        s.seed_realised.strength,
        pct(s.seed_realised.shape_error, 1),
        s.checked.least_normal,
    );
    if s.checked.poor {
        line.push_str(", POOR");
    }
    for note in &s.checked.notes {
        line.push_str("; ");
        line.push_str(note);
    }
    line
}

/// `platefield study probes`: runs every section and writes `probes.md` to
/// `out`; the engine's timings go to stderr only.
pub fn run(out: &Path) -> Result<String> {
    let cache = Path::new(CACHE);
    let mut md = String::from(
        "# Probes: the measurements behind numbers the docs state\n\n\
         Each section measures what a module's docs or `docs/` cite (see `studies/src/probes/`). \
         Regenerate: `platefield study probes` (the engine's timings are printed, not written).\n",
    );
    md.push_str(&saddle_cap::section(cache)?);
    md.push_str(&transport::section(cache)?);
    md.push_str(&lag_window::section()?);
    md.push_str(&saddle_parts::section(cache)?);
    md.push_str(&engine::section());
    let path = out.join("probes.md");
    write_atomic(&path, md.as_bytes())?;
    let _ = writeln!(md, "wrote {}", path.display());
    Ok(md)
}
