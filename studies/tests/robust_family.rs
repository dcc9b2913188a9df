//! A seeded subset of the random target family (`results/robust_family.md`
//! holds the whole family, `platefield study robust-family`): a sink, an
//! ellipse, a saddle and a whirlpool, each with its own friction range.

use platefield::design::method::Method;
use platefield::request::family::family;
use platefield_studies::robust_family::{affine_residual, outcome, COUNT, GOALS, SEED};

/// The mirror-image (or counter-rotating) share of each member holds its
/// worst shape error over the range ≤ 10 % (the bound for every
/// target), no worse than the nominal synthesized motion's worst case over
/// the range (+ 0.5 percentage point), at ≥ 60 % of that motion's
/// strength at its own μ (the goal). Each is judged at five
/// frictions over its range. The `mirror` and `synthesize` methods stand
/// in for `auto` (which adds the sequenced candidate and costs about three
/// times as much).
fn holds_over_friction(t: &platefield::request::Target) {
    let o = outcome(t, (Method::Mirror, Method::Synthesize), true).unwrap();
    let (shape, _) = o.robust.worst();
    let (nominal, _) = o.nominal.worst();
    let ratio = o.strength_ratio();
    eprintln!(
        "{}: robust {shape:.4}, nominal {nominal:.4}, ratio {ratio:.3} ({:.1} s of CPU)",
        t.name, o.cpu_s
    );
    assert!(shape <= 0.10, "{}: worst shape {shape}", t.name);
    assert!(
        shape <= nominal + 0.005,
        "{}: {shape} against the nominal {nominal}",
        t.name
    );
    assert!(ratio >= 0.6, "{}: strength ratio {ratio}", t.name);
}

/// The seeded subset of four: an off-centre sink; an ellipse, whose
/// mirror line is at a random angle; an off-centre saddle, whose mirror
/// lines miss the plate's centre; and a whirlpool, without a mirror line
/// (the counter-rotating share, a second synthesis). Measured: worst
/// 4.6 %, 5.9 %, 4.5 %, 6.1 % against the nominal motion's 8.0 %, 8.4 %,
/// 7.5 %, 9.9 %; strength ratios 0.69, 0.65, 0.69, 0.69; 17, 16, 31 and
/// 19 s of CPU: `cargo test --release -p platefield-studies --test
/// robust_family -- --ignored --nocapture subset`. The default run keeps
/// the ellipse ([`the_ellipse_member_holds_over_friction`]).
#[test]
#[ignore = "about 85 s of CPU: cargo test --release -p platefield-studies --test robust_family -- --ignored --nocapture subset"]
fn a_seeded_subset_of_the_family_holds_over_friction() {
    let members = family(SEED, 4);
    let kinds: Vec<&str> = members
        .iter()
        .map(|t| t.name.split('_').next().unwrap_or(""))
        .collect();
    assert_eq!(kinds, ["sink", "ellipse", "saddle", "whirlpool"]);
    members.iter().for_each(holds_over_friction);
}

/// The subset's ellipse: its mirror line is at a random angle, off any
/// lattice of axes (the failure issue 45 opens with). Measured: worst
/// 5.9 % against the nominal 8.4 %, strength ratio 0.65, about 16 s of
/// CPU.
#[test]
fn the_ellipse_member_holds_over_friction() {
    let members = family(SEED, 4);
    assert!(
        members[1].name.starts_with("ellipse_"),
        "{}",
        members[1].name
    );
    holds_over_friction(&members[1]);
}

/// What the subset relies on to judge the nominal motion without
/// designing it (`platefield_studies::robust_family::outcome`): the
/// schedule `mirror` builds its shares from, designing a member over its
/// range, has the segments of `synthesize`'s design of the same member at
/// the range's middle, byte for byte. Checked on the ellipse and the
/// whirlpool (a mirror share and a counter-rotating one; about 40 s of
/// CPU): `cargo test --release -p platefield-studies --test robust_family
/// -- --ignored`.
#[test]
#[ignore = "about 40 s of CPU: cargo test --release -p platefield-studies --test robust_family -- --ignored"]
fn the_mirror_base_is_the_nominal_synthesis() {
    use platefield::design::DesignOptions;
    use platefield::inverse::run;
    use platefield::request::FrictionSpec;
    let design = |t: &platefield::request::Target, method| {
        let opts = DesignOptions {
            method,
            runtime: platefield::work::Runtime::QUIET,
            ..DesignOptions::default()
        };
        run(t, &opts).unwrap().into_method().unwrap()
    };
    let members = family(SEED, 4);
    for t in [&members[1], &members[3]] {
        let ranged = design(t, Method::Mirror);
        let base = ranged.synthesized.expect("the shares' motion");
        let mut nominal = t.clone();
        let spec = t.friction.expect("a family member states its range");
        nominal.friction = Some(FrictionSpec::exact(spec.nominal()));
        let exact = design(&nominal, Method::Synthesize);
        assert_eq!(base.segments, exact.kept().schedule.segments, "{}", t.name);
        assert_eq!(base.settings, exact.kept().schedule.settings, "{}", t.name);
    }
}

/// Why the family's sampled members miss the 10 % bound
/// (`results/robust_family.md`): each asks for more than an affine field
/// can give ([`affine_residual`] over its sample points above 10 %), and
/// the committed robust design of each leaves at least 85 % of that
/// residual unmatched: no design here reaches the non-affine part. (Basis
/// copies shifted by 2 cm fit sampled_4 to 7 % on paper, below its 13.8 %
/// residual, but the sequence of them loses contact at the region's
/// corners: `design sampled_4.json --method sequence --shift 0.02,0
/// --shift=-0.02,0 --shift 0,0.02 --shift 0,-0.02`, the member written
/// out with its range's middle as its friction.) A committed row that beats
/// its residual by more fails this test: good news, to be written into the
/// study's reading.
#[test]
fn sampled_members_miss_by_their_non_affine_part() {
    let md = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/robust_family.md"
    ))
    .unwrap();
    let members = family(SEED, COUNT);
    let sampled: Vec<_> = members
        .iter()
        .filter(|t| t.name.starts_with("sampled_"))
        .collect();
    assert_eq!(sampled.len(), 5);
    for t in sampled {
        let residual = affine_residual(&t.field).expect("a sampled field");
        let row = md
            .lines()
            .find(|l| l.starts_with(&format!("| {} |", t.name)))
            .unwrap_or_else(|| panic!("{}: no row", t.name));
        // Column 5: "robust worst shape (at μ)", as "14.5 % (0.432)".
        let cell = row.split('|').nth(5).unwrap().trim();
        let worst: f64 = cell.split(' ').next().unwrap().parse::<f64>().unwrap() / 100.0;
        eprintln!(
            "{}: affine residual {:.1} %, robust worst {:.1} %",
            t.name,
            100.0 * residual,
            100.0 * worst
        );
        assert!(residual > GOALS.1, "{}: affine residual {residual}", t.name);
        assert!(
            worst >= 0.85 * residual,
            "{}: robust worst {worst} against the affine residual {residual}",
            t.name
        );
    }
    // An analytic field has no such residual.
    assert_eq!(affine_residual(&members[0].field), None);
}
