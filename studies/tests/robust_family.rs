//! A seeded subset of the random target family (`results/robust_family.md`
//! holds the whole family, `platefield study robust-family`): a sink, an
//! ellipse, a saddle and a whirlpool, each with its own friction range.

use platefield::design::method::Method;
use platefield::request::family::family;
use platefield_studies::robust_family::{outcome, SEED};

/// The mirror-image (or counter-rotating) share of each, judged at five
/// frictions over its range, holds its worst shape error ≤ 10 % (the
/// issue's bound for every target), no worse than the nominal synthesized
/// motion's worst case over the range (+ 0.5 percentage point), at ≥ 60 %
/// of that motion's strength at its own μ (the goal). The four: an off-centre sink;
/// an ellipse, whose mirror line is at a random angle; an off-centre
/// saddle, whose mirror lines miss the plate's centre; and a whirlpool,
/// without a mirror line (the counter-rotating share, a second
/// synthesis). Measured: worst 4.6 %, 5.9 %, 4.5 %, 6.1 % against the
/// nominal motion's 8.0 %, 8.4 %, 7.5 %, 9.9 %; strength ratios 0.69,
/// 0.65, 0.69, 0.69; about 100 s of CPU. The `mirror` and `synthesize`
/// methods stand in for `auto` (which adds the sequenced candidate and
/// costs about three times as much).
#[test]
fn a_seeded_subset_of_the_family_holds_over_friction() {
    let members = family(SEED, 4);
    let kinds: Vec<&str> = members
        .iter()
        .map(|t| t.name.split('_').next().unwrap_or(""))
        .collect();
    assert_eq!(kinds, ["sink", "ellipse", "saddle", "whirlpool"]);
    for t in &members {
        let o = outcome(t, (Method::Mirror, Method::Synthesize), true).unwrap();
        let (shape, _) = o.robust.worst();
        let (nominal, _) = o.nominal.worst();
        let ratio = o.strength_ratio();
        eprintln!(
            "{}: robust {shape:.4}, nominal {nominal:.4}, ratio {ratio:.3}",
            t.name
        );
        assert!(shape <= 0.10, "{}: worst shape {shape}", t.name);
        assert!(
            shape <= nominal + 0.005,
            "{}: {shape} against the nominal {nominal}",
            t.name
        );
        assert!(ratio >= 0.6, "{}: strength ratio {ratio}", t.name);
    }
}
