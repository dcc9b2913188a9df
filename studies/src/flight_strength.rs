//! Designs that may fly: how much realised strength brief flight buys the
//! sink and the saddle at a judged shape error of at most 5 %
//! (`platefield study flight-strength` writes `flight_strength.md`).
//!
//! **The shakers** ([`SHAKERS`]; every comparison is on one): the shaker
//! that plays each target's shipped sequenced schedule
//! (`results/<name>/schedule.json`: its per-axis peaks and period,
//! [`platefield::design::method::sequenced_limits`], harmonics 1 and 2) —
//! the shaker `design --method auto` gives its synthesis when the target
//! states none — and the default envelope ([`ShakerLimits::envelope`]),
//! which `design --method synthesize` uses then.
//!
//! **The baseline** is today's product: the shipped kept design's judged
//! strength and shape error, and the contact synthesis
//! (`design --method synthesize` with the target's `shaker` set to those
//! limits) at contact margins m = 0.3, 0.25, 0.2, 0.1 and 0, judged by the
//! product's judge (each point held, contact only). The baseline strength
//! is the strongest judged at a shape error ≤ [`SHAPE_LIMIT`].
//!
//! **Flight.** Each contact synthesis's tilt signals (angular x and y,
//! every harmonic) are then scaled by c = 1, 1.1, … while their peaks stay
//! within the shaker's angular limits: more tilt, more strength, and a
//! normal force that reaches 0 at the region's corners for part of the
//! cycle. Each scaled motion is judged with the flight rung
//! ([`judge_flying`]): at the judge's points, the steady orbit of a held
//! point part followed through its flights
//! ([`platefield::dynamics::Simulator::held_orbit`]), its period-mean
//! velocity the realised field and its time in flight over the period the
//! airborne fraction; realised strength and shape error as the judge's. A
//! motion is admitted when its largest airborne fraction over the points
//! is ≤ [`MAX_FLIGHT`] and its shape error ≤ [`SHAPE_LIMIT`]; the ratio is
//! its strength over the baseline's.
//!
//! The flying judge plays each point as the product's judge does, its
//! kinematics held at the point ([`Model::FROZEN`]; a part in flight
//! flies from it, `src/dynamics/flight.rs`), and differs from it on a
//! motion that never leaves the plate only by its settling rule (the
//! period mean changing by less than 1e-5 μ g T, against the judge's
//! transient estimate): the c = 1 rows of the contact motions state both,
//! and `studies/tests/flight_strength.rs` holds them together.

use std::fmt::Write as _;
use std::path::Path;

use rayon::prelude::*;

use platefield::design::judge::judge_points;
use platefield::design::method::sequenced_limits;
use platefield::design::{DesignOptions, Method};
use platefield::dynamics::{Flight, Model};
use platefield::error::{Error, Result};
use platefield::field::FieldSettings;
use platefield::inverse::{run as design_run, DesignOutcome};
use platefield::motion::{Motion, Signals};
use platefield::output::write_atomic;
use platefield::request::{ShakerSpec, Target};
use platefield::schedule::Schedule;
use platefield::synth::ShakerLimits;

/// Default output folder.
pub const DIR: &str = "results";

/// The targets of the study.
pub const TARGETS: [&str; 2] = ["sink", "saddle"];

/// The shakers of the study: `sequenced`, the per-axis peaks and period of
/// the target's shipped sequenced schedule (what `design --method auto`
/// gives its synthesis when the target states no `shaker`); `envelope`,
/// the default limits [`ShakerLimits::envelope`] (what `design --method
/// synthesize` uses then).
pub const SHAKERS: [&str; 2] = ["sequenced", "envelope"];

/// The contact margins (fractions of g) of the contact syntheses.
pub const MARGINS: [f64; 5] = [0.3, 0.25, 0.2, 0.1, 0.0];

/// The tilt scales tried on each contact synthesis (those whose angular
/// peaks stay within the shaker's limits).
pub const TILT_SCALES: [f64; 8] = [1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.8];

/// Largest airborne fraction a design that may fly is allowed.
pub const MAX_FLIGHT: f64 = 0.1;

/// Largest judged shape error the comparison admits.
pub const SHAPE_LIMIT: f64 = 0.05;

/// The strength ratio asked for against the baseline.
pub const RATIO_ASKED: f64 = 1.3;

/// Samples per period of the peak search.
const PEAK_SAMPLES: usize = 4096;

/// A motion judged with the flight rung.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlyingJudge {
    /// Realised strength ŝ (s⁻¹ for a unit-strength target).
    pub strength: f64,
    /// Realised shape error.
    pub shape_error: f64,
    /// Largest airborne fraction over the points.
    pub max_airborne: f64,
    /// Mean airborne fraction over the points.
    pub mean_airborne: f64,
    /// Points where the part flies at all.
    pub flying_points: usize,
    /// Points played.
    pub points: usize,
    /// Points whose orbit did not settle or lost the part.
    pub unsettled: usize,
}

/// `motion` judged with the flight rung at `target`'s judge points
/// (module documentation): realised strength and shape error with the
/// target's weights, and the airborne fractions.
///
/// # Errors
/// The target's sampling, or a simulator refusing flight.
pub fn judge_flying(
    target: &Target,
    motion: &Motion,
    settings: &FieldSettings,
) -> Result<FlyingJudge> {
    let sampled = target
        .sample()
        .map_err(|e| Error::invalid("target", e.to_string()))?;
    let points = judge_points(target, &sampled);
    let frozen = FieldSettings {
        model: Model::FROZEN,
        ..*settings
    };
    let sim = frozen.simulator(motion).with_flight(Flight::INELASTIC)?;
    let orbits: Vec<_> = points
        .par_iter()
        .map(|&i| sim.held_orbit(sampled.points[i]).ok())
        .collect();
    let (mut rt, mut tt, mut rr) = (0.0, 0.0, 0.0);
    let (mut max_air, mut sum_air, mut flying, mut unsettled, mut n) = (0.0_f64, 0.0, 0, 0, 0);
    for (&i, o) in points.iter().zip(&orbits) {
        let Some(o) = o.filter(|o| o.settled) else {
            unsettled += 1;
            continue;
        };
        let (w2, t, r) = (
            sampled.weights[i] * sampled.weights[i],
            sampled.vectors[i],
            o.velocity,
        );
        rt += w2 * (r[0] * t[0] + r[1] * t[1]);
        tt += w2 * (t[0] * t[0] + t[1] * t[1]);
        rr += w2 * (r[0] * r[0] + r[1] * r[1]);
        max_air = max_air.max(o.airborne_fraction);
        sum_air += o.airborne_fraction;
        flying += usize::from(o.airborne_fraction > 0.0);
        n += 1;
    }
    let s = if tt > 0.0 { rt / tt } else { 0.0 };
    let shape_error = if s > 0.0 {
        ((rr - s * rt).max(0.0) / (s * s * tt)).sqrt()
    } else {
        f64::INFINITY
    };
    Ok(FlyingJudge {
        strength: s,
        shape_error,
        max_airborne: max_air,
        mean_airborne: if n > 0 { sum_air / n as f64 } else { 0.0 },
        flying_points: flying,
        points: points.len(),
        unsettled,
    })
}

/// The largest |value| over one period of each of `signals`' six summed
/// acceleration signals (linear x, y, z, angular x, y, z).
pub fn peaks(signals: &Signals) -> [f64; 6] {
    let w = std::f64::consts::TAU / signals.period;
    let axes = [
        &signals.linear.x,
        &signals.linear.y,
        &signals.linear.z,
        &signals.angular.x,
        &signals.angular.y,
        &signals.angular.z,
    ];
    std::array::from_fn(|k| {
        (0..PEAK_SAMPLES)
            .map(|i| {
                let t = signals.period * i as f64 / PEAK_SAMPLES as f64;
                axes[k]
                    .iter()
                    .map(|f| f.amplitude * (f64::from(f.harmonic) * w * t + f.phase).sin())
                    .sum::<f64>()
                    .abs()
            })
            .fold(0.0, f64::max)
    })
}

/// `signals` with its tilt signals (angular x and y) scaled by `c`.
pub fn tilted(signals: &Signals, c: f64) -> Signals {
    let mut s = signals.clone();
    for term in s.angular.x.iter_mut().chain(s.angular.y.iter_mut()) {
        term.amplitude *= c;
    }
    s
}

/// One contact synthesis: its margin, its motion, the product's judge of
/// it, and the settings it was designed and played with.
#[derive(Debug, Clone)]
pub struct ContactDesign {
    /// Contact margin (fraction of g).
    pub margin: f64,
    /// The synthesized motion.
    pub signals: Signals,
    /// The product's judged strength.
    pub strength: f64,
    /// The product's judged shape error.
    pub shape_error: f64,
    /// The simulation settings of the design.
    pub settings: FieldSettings,
}

/// The shipped kept design of `name`: its method, judged strength and
/// shape error (`results/<name>/schedule.json`).
///
/// # Errors
/// The file unreadable or without a judged strength.
pub fn shipped(results: &Path, name: &str) -> Result<(String, f64, f64, Schedule)> {
    let schedule = Schedule::load(&results.join(name).join("schedule.json"))?;
    let played = schedule
        .played
        .as_ref()
        .ok_or_else(|| Error::invalid("schedule.played", "missing"))?;
    let (Some(s), Some(e)) = (played.realised_strength, played.realised_shape_error) else {
        return Err(Error::invalid(
            "schedule.played.realised_strength",
            "missing",
        ));
    };
    Ok((
        format!("{:?}", played.method).to_lowercase(),
        s,
        e,
        schedule,
    ))
}

/// The contact synthesis of `target` on `limits` with contact margin
/// `margin`, designed and judged by `design --method synthesize`.
///
/// # Errors
/// The design's.
pub fn contact_design(
    target: &Target,
    limits: &ShakerLimits,
    margin: f64,
) -> Result<ContactDesign> {
    let mut t = target.clone();
    let l = ShakerLimits {
        contact_margin: margin,
        ..limits.clone()
    };
    t.shaker = Some(ShakerSpec {
        period: Some(l.period),
        linear: Some(l.linear),
        angular: Some(l.angular),
        harmonics: Some(l.harmonics),
        contact_margin: Some(l.contact_margin),
        ..ShakerSpec::default()
    });
    let opts = DesignOptions {
        method: Method::Synthesize,
        runtime: platefield::work::Runtime::QUIET,
        ..DesignOptions::default()
    };
    let DesignOutcome::Method(md) = design_run(&t, &opts)? else {
        return Err(Error::invalid("method", "expected a method design"));
    };
    let schedule = md
        .candidates
        .into_iter()
        .find(|c| c.method == Method::Synthesize)
        .map(|c| c.schedule)
        .ok_or_else(|| Error::invalid("method", "no synthesized candidate"))?;
    let signals = schedule
        .segments
        .iter()
        .find_map(|s| s.motion.clone())
        .ok_or_else(|| Error::invalid("schedule.segments", "no synthesized motion"))?;
    let played = schedule
        .played
        .as_ref()
        .ok_or_else(|| Error::invalid("schedule.played", "missing"))?;
    Ok(ContactDesign {
        margin,
        signals,
        strength: played.realised_strength.unwrap_or(f64::NAN),
        shape_error: played.realised_shape_error.unwrap_or(f64::NAN),
        settings: schedule.settings,
    })
}

/// One row of the flight table.
#[derive(Debug, Clone, Copy)]
pub struct FlightRow {
    /// Contact margin of the synthesis scaled.
    pub margin: f64,
    /// Tilt scale c.
    pub scale: f64,
    /// Largest tilt peak over its limit.
    pub tilt_use: f64,
    /// The flying judge.
    pub judged: FlyingJudge,
}

impl FlightRow {
    /// Within the airborne and shape limits.
    pub fn admitted(&self) -> bool {
        self.judged.max_airborne <= MAX_FLIGHT && self.judged.shape_error <= SHAPE_LIMIT
    }
}

/// One target's study.
#[derive(Debug, Clone)]
pub struct TargetStudy {
    /// Target name.
    pub name: String,
    /// The shaker ([`SHAKERS`]).
    pub shaker: String,
    /// The shipped design: method, strength, shape error.
    pub shipped: (String, f64, f64),
    /// The contact syntheses.
    pub contact: Vec<ContactDesign>,
    /// The tilt-scaled motions judged with flight.
    pub rows: Vec<FlightRow>,
}

impl TargetStudy {
    /// The baseline: the strongest of today's designs judged at a shape
    /// error ≤ [`SHAPE_LIMIT`], and what it is.
    pub fn baseline(&self) -> (f64, String) {
        let mut best = (0.0, String::new());
        if self.shipped.2 <= SHAPE_LIMIT {
            best = (self.shipped.1, format!("shipped {}", self.shipped.0));
        }
        for c in &self.contact {
            if c.shape_error <= SHAPE_LIMIT && c.strength > best.0 {
                best = (
                    c.strength,
                    format!("synthesize, contact margin {} g", c.margin),
                );
            }
        }
        best
    }

    /// The strongest admitted flying row.
    pub fn best_flying(&self) -> Option<FlightRow> {
        self.rows
            .iter()
            .filter(|r| r.admitted())
            .copied()
            .max_by(|a, b| a.judged.strength.total_cmp(&b.judged.strength))
    }
}

/// The study of `name` (`targets/<name>.json` against
/// `results/<name>/schedule.json`).
///
/// # Errors
/// The target, the shipped schedule, a design or a simulator.
pub fn study_target(
    name: &str,
    shaker: &str,
    targets: &Path,
    results: &Path,
) -> Result<TargetStudy> {
    let target = Target::load(&targets.join(format!("{name}.json")))?;
    let (method, s, e, schedule) = shipped(results, name)?;
    let limits = match shaker {
        "envelope" => ShakerLimits::envelope(),
        _ => sequenced_limits(&schedule, &ShakerLimits::envelope())?,
    };
    let contact: Vec<ContactDesign> = MARGINS
        .iter()
        .map(|&m| contact_design(&target, &limits, m))
        .collect::<Result<_>>()?;
    let mut rows = Vec::new();
    for c in &contact {
        let p = peaks(&c.signals);
        let use_of = |k: usize| {
            if limits.angular[k] > 0.0 {
                p[3 + k] / limits.angular[k]
            } else {
                0.0
            }
        };
        let tilt = use_of(0).max(use_of(1));
        for &scale in &TILT_SCALES {
            if tilt * scale > 1.0 + 1e-9 {
                continue;
            }
            let motion = Motion::Signals(tilted(&c.signals, scale));
            let judged = judge_flying(&target, &motion, &c.settings)?;
            rows.push(FlightRow {
                margin: c.margin,
                scale,
                tilt_use: tilt * scale,
                judged,
            });
        }
    }
    Ok(TargetStudy {
        name: name.to_string(),
        shaker: shaker.to_string(),
        shipped: (method, s, e),
        contact,
        rows,
    })
}

/// The report of `studies`.
pub fn report(studies: &[TargetStudy]) -> String {
    let pct = |x: f64| platefield::output::percent(x, 2);
    let mut md = String::new();
    md.push_str("# Designs that may fly: strength at a judged shape error ≤ 5 %\n\n");
    md.push_str("Regenerate: `platefield study flight-strength`.\n\n");
    md.push_str(
        "Two shakers: `sequenced`, the per-axis peaks and period of the target's shipped sequenced schedule, harmonics 1 and 2 (the shaker `design --method auto` gives its synthesis); `envelope`, the default limits (`ShakerLimits::envelope`; the shaker `design --method synthesize` uses). Every comparison is on one shaker. Baseline: the strongest of today's designs judged at a shape error ≤ 5 % — the shipped kept design, or the contact synthesis (`design --method synthesize`, the target's `shaker` set to those limits) at contact margin m. Flight: each contact synthesis with its tilt signals scaled by c (within the angular limits), judged with the flight rung — at the judge's points the steady orbit of a held point part followed through its flights (`Simulator::held_orbit`); airborne fraction, the time in flight over the period (largest and mean over the points). Admitted: largest airborne fraction ≤ 10 % and shape error ≤ 5 %. The study's module docs (`studies/src/flight_strength.rs`) state the method.\n\n",
    );
    for st in studies {
        let (base, what) = st.baseline();
        let _ = writeln!(md, "## {}, {} shaker\n", st.name, st.shaker);
        let _ = writeln!(
            md,
            "Shipped kept design ({}): strength {:.4} at shape error {}.\n",
            st.shipped.0,
            st.shipped.1,
            pct(st.shipped.2)
        );
        md.push_str(
            "| contact margin (g) | judged strength | judged shape error |\n|---|---|---|\n",
        );
        for c in &st.contact {
            let _ = writeln!(
                md,
                "| {} | {:.4} | {} |",
                c.margin,
                c.strength,
                pct(c.shape_error)
            );
        }
        let _ = writeln!(
            md,
            "\nBaseline (strongest at shape error ≤ 5 %): {base:.4} ({what}); {RATIO_ASKED}× is {:.4}.\n",
            RATIO_ASKED * base
        );
        md.push_str("| from margin (g) | tilt scale c | tilt peak / limit | strength | shape error | airborne, largest | airborne, mean | points flying | unsettled | admitted | ratio |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
        for r in &st.rows {
            let j = &r.judged;
            let _ = writeln!(
                md,
                "| {} | {:.1} | {:.3} | {:.4} | {} | {} | {} | {} / {} | {} | {} | {:.3} |",
                r.margin,
                r.scale,
                r.tilt_use,
                j.strength,
                pct(j.shape_error),
                pct(j.max_airborne),
                pct(j.mean_airborne),
                j.flying_points,
                j.points,
                j.unsettled,
                if r.admitted() { "yes" } else { "no" },
                j.strength / base
            );
        }
        match st.best_flying() {
            Some(b) if b.judged.max_airborne > 0.0 => {
                let _ = writeln!(
                    md,
                    "\nStrongest admitted motion that flies: margin {} g, c = {:.1}: {:.4} at {} (airborne ≤ {}), {:.3}× the baseline: the {RATIO_ASKED}× asked is {}.\n",
                    b.margin,
                    b.scale,
                    b.judged.strength,
                    pct(b.judged.shape_error),
                    pct(b.judged.max_airborne),
                    b.judged.strength / base,
                    if b.judged.strength >= RATIO_ASKED * base { "reached" } else { "not reached" }
                );
            }
            Some(b) => {
                let _ = writeln!(
                    md,
                    "\nNo admitted motion flies; the strongest admitted stays in contact: margin {} g, c = {:.1}: {:.4} at {}, {:.3}× the baseline: the {RATIO_ASKED}× asked is not reached by flight.\n",
                    b.margin,
                    b.scale,
                    b.judged.strength,
                    pct(b.judged.shape_error),
                    b.judged.strength / base
                );
            }
            None => md.push_str("\nNo motion is admitted.\n\n"),
        }
    }
    md
}

/// Runs the study on the shipped targets and results and writes
/// `flight_strength.md` to `out`.
///
/// # Errors
/// The study's, or writing the file.
pub fn run(out: &Path) -> Result<String> {
    let mut studies = Vec::new();
    for shaker in SHAKERS {
        for name in TARGETS {
            studies.push(study_target(
                name,
                shaker,
                Path::new("targets"),
                Path::new("results"),
            )?);
        }
    }
    let md = report(&studies);
    let path = out.join("flight_strength.md");
    write_atomic(&path, md.as_bytes())?;
    Ok(format!("{md}\nwrote {}\n", path.display()))
}
