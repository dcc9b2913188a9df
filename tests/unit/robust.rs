//! Designs that hold over the parts' friction: the mirror-image
//! time-shares (`design::mirror`) and their symmetry argument.

use crate::design::method::judge_check;
use crate::design::mirror::{
    counter_share, mirror_axis, mirror_share, MirrorLine, MIRROR_SEGMENT_CYCLES,
};
use crate::dynamics::Friction;
use crate::field::{Field, FieldKind, FieldSettings, Grid};
use crate::motion::{Motion, Signals};
use crate::play::sensitivity::{friction_sweep, FrictionRow};
use crate::request::Target;
use crate::schedule::Schedule;
use crate::synth::ShakerLimits;

/// The mirror motion's field is the mirror image of the field, at μ 0.2
/// and 0.45: V′(x, y) = (Vx(x, −y), −Vy(x, −y)) on a grid symmetric in y
/// (and mirrored about the 90° plane, x → −x, through the turns of
/// `mirrored_about`: V′(x, y) = (−Vx(−x, y), Vy(−x, y))),
/// to 1e-9 of the field's largest vector (the reflection is exact; only
/// rounding differs). A sign slip in any of the three mirrored signals
/// breaks it at the 1e-1 level.
#[test]
fn the_mirror_motions_field_is_the_mirror_image_at_every_friction() {
    let motion = Signals::example();
    let grid = Grid {
        x: [-0.03, 0.03],
        y: [-0.03, 0.03],
        n: [7, 7],
    };
    let [nx, ny] = grid.n;
    for mu in [0.2, 0.45] {
        let (worst, scale) = mirror_mismatch(
            (&motion, &motion.mirrored_y()),
            &grid,
            mu,
            (|ix, iy| (ny - 1 - iy) * nx + ix, [1.0, -1.0]),
        );
        assert!(worst <= 1e-9 * scale, "μ {mu}: {worst:e} of {scale:e}");
    }
}

/// The largest |V′(S p) − M V(p)| over `grid`'s points p at μ, with the
/// largest |V| (asserted large enough to compare): V the field of
/// `motion`, V′ of its `mirrored` image, `image(ix, iy)` the index of
/// S p, `sign` the diagonal of M.
fn mirror_mismatch(
    (motion, mirrored): (&Signals, &Signals),
    grid: &Grid,
    mu: f64,
    (image, sign): (impl Fn(usize, usize) -> usize, [f64; 2]),
) -> (f64, f64) {
    let settings = FieldSettings {
        friction: Friction::uniform(mu),
        ..FieldSettings::default()
    };
    let field = |m: &Signals| {
        Field::compute(
            &Motion::Signals(m.clone()),
            grid,
            FieldKind::Velocity,
            &settings,
            &|| {},
        )
    };
    let (f, g) = (field(motion), field(mirrored));
    let scale = f
        .vectors
        .iter()
        .map(|v| v[0].hypot(v[1]))
        .fold(0.0, f64::max);
    assert!(scale > 1e-4, "a field to compare: {scale}");
    let [nx, ny] = grid.n;
    let mut worst = 0.0_f64;
    for iy in 0..ny {
        for ix in 0..nx {
            let (a, b) = (f.vectors[iy * nx + ix], g.vectors[image(ix, iy)]);
            worst = worst.max((b[0] - sign[0] * a[0]).hypot(b[1] - sign[1] * a[1]));
        }
    }
    (worst, scale)
}

/// Which shipped targets the reflection y → −y maps to themselves.
#[test]
fn symmetric_targets_are_recognised() {
    for (name, axis) in [
        ("sink", Some(0.0)),
        ("saddle", Some(0.0)),
        ("line_sink", Some(0.0)),
        ("whirlpool", None),
        ("squeeze_trans", Some(0.0)),
        // A LineSink along 30° through (5 mm, 0): mirrored in any line
        // across it; the one through the centre is at 120°.
        ("line_sink_30", Some(120.0)),
    ] {
        let t = Target::load(std::path::Path::new(&format!("targets/{name}.json"))).unwrap();
        let s = t.sample().unwrap();
        let found = mirror_axis(&t, &s);
        assert_eq!(found.map(|l| l.angle_deg), axis, "{name}");
        assert!(
            found.is_none_or(|l| l.point == [0.0, 0.0]),
            "{name}: {found:?}"
        );
    }
}

/// A seeded xorshift generator of uniform numbers in [0, 1).
fn seeded(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The target `json` (without a grid) on a ±4 cm, 21 × 21 grid.
fn on_grid(json: &str) -> Target {
    let grid = r#"{"grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]}, "#;
    Target::from_json_str(&json.replacen('{', grid, 1)).unwrap()
}

/// Symmetry axes at any angle through the plate centre, on seeded random
/// targets: a sink centred at c is symmetric in the line through the
/// centre and c, a line sink at angle θ off the centre in every line
/// across it (the one through the centre at θ + 90°), an elliptic sink of
/// two line sinks in both of their lines. Each axis found within 1e-6°.
#[test]
fn symmetry_axes_are_found_at_any_angle() {
    let mut uniform = seeded(0x2545_f491_4f6c_dd1d);
    let axis = |json: &str| {
        let t = on_grid(json);
        let line = mirror_axis(&t, &t.sample().unwrap());
        assert!(line.is_none_or(|l| l.point == [0.0, 0.0]), "{line:?}");
        line.map(|l| l.angle_deg)
    };
    let near = |a: f64, b: f64| {
        let d = (a - b).rem_euclid(180.0);
        d.min(180.0 - d) < 1e-6
    };
    for _ in 0..8 {
        let (r, phi) = (0.015 * (0.2 + uniform()), 360.0 * uniform());
        let c = [r * phi.to_radians().cos(), r * phi.to_radians().sin()];
        let found = axis(&format!(
            r#"{{"name": "s", "field": {{"kind": "sink", "center": [{}, {}]}}}}"#,
            c[0], c[1]
        ))
        .expect("an off-centre sink is symmetric");
        assert!(near(found, phi), "sink at {c:?}: {found} against {phi}");
        let (theta, offset) = (180.0 * uniform(), 0.01 * (uniform() - 0.5));
        let found = axis(&format!(
            r#"{{"name": "l", "field": {{"kind": "line_sink", "angle": {theta}, "offset": {offset}}}}}"#
        ))
        .expect("a line sink is symmetric");
        assert!(near(found, theta + 90.0), "line sink at {theta}°: {found}");
        let w = 0.3 + 0.7 * uniform();
        let found = axis(&format!(
            r#"{{"name": "e", "field": {{"kind": "sum", "terms": [
                {{"field": {{"kind": "line_sink", "angle": {theta}, "strength": 1}}}},
                {{"field": {{"kind": "line_sink", "angle": {}, "strength": {w}}}}}]}}}}"#,
            theta + 90.0
        ))
        .expect("an elliptic sink is symmetric");
        assert!(
            near(found, theta) || near(found, theta + 90.0),
            "ellipse at {theta}°: {found}"
        );
    }
    // A whirlpool has none.
    assert_eq!(
        axis(r#"{"name": "w", "field": {"kind": "whirlpool"}}"#),
        None
    );
}

/// Symmetry lines off the centre, on seeded random targets whose only
/// mirror lines miss it: a saddle centred at c along θ is symmetric in
/// its own two axes (θ and θ + 90° through c), an elliptic sink centred
/// at c (two line sinks through c) in the same two. Each found within
/// 1e-6° and its line through c within 1e-9 m; a whirlpool off the centre
/// has none.
#[test]
fn symmetry_lines_off_the_centre_are_found() {
    let mut uniform = seeded(0x9e37_79b9_7f4a_7c15);
    let line = |json: &str| {
        let t = on_grid(json);
        mirror_axis(&t, &t.sample().unwrap())
    };
    let on_axes = |l: MirrorLine, theta: f64, c: [f64; 2]| {
        let d = (l.angle_deg - theta).rem_euclid(90.0);
        let (s, co) = l.angle_deg.to_radians().sin_cos();
        let through_c = (-s * c[0] + co * c[1] - l.offset()).abs();
        d.min(90.0 - d) < 1e-6 && through_c < 1e-9
    };
    for _ in 0..6 {
        let c = [0.03 * (uniform() - 0.5), 0.03 * (uniform() - 0.5)];
        let theta = 180.0 * uniform();
        let found = line(&format!(
            r#"{{"name": "s", "field": {{"kind": "saddle", "center": [{}, {}], "angle": {theta}}}}}"#,
            c[0], c[1]
        ))
        .expect("an off-centre saddle is symmetric");
        assert!(
            on_axes(found, theta, c),
            "saddle at {c:?}, {theta}°: {found:?}"
        );
        assert!(found.point != [0.0, 0.0], "{found:?}");
        let w = 0.3 + 0.6 * uniform();
        let found = line(&format!(
            r#"{{"name": "e", "field": {{"kind": "sum", "terms": [
                {{"field": {{"kind": "line_sink", "center": [{0}, {1}], "angle": {theta}, "strength": 1}}}},
                {{"field": {{"kind": "line_sink", "center": [{0}, {1}], "angle": {2}, "strength": {w}}}}}]}}}}"#,
            c[0],
            c[1],
            theta + 90.0
        ))
        .expect("an off-centre elliptic sink is symmetric");
        assert!(
            on_axes(found, theta, c),
            "ellipse at {c:?}, {theta}°: {found:?}"
        );
    }
    assert_eq!(
        line(r#"{"name": "w", "field": {"kind": "whirlpool", "center": [0.01, 0.004]}}"#),
        None
    );
}

/// The mirror motion in a line off the centre (`Signals::mirrored_in`)
/// has the mirror image of the field, at μ 0.2 and 0.45: for the line at
/// 90° through (5 mm, 0), S(x, y) = (10 mm − x, y) maps the grid x ∈
/// [−20, 30] mm to itself, and V′(x, y) = (−Vx(10 mm − x, y), Vy(…)).
/// The shift's vertical lever is first order in the tilts
/// (`Signals::transformed`), so the match is to 1e-3 of the field's
/// largest vector (measured 5.4e-4 at μ 0.2; a sign slip or a wrong
/// reference point breaks it at the 1e-1 level).
#[test]
fn the_mirror_motion_in_a_line_off_the_centre_mirrors_the_field() {
    let motion = Signals::example();
    let grid = Grid {
        x: [-0.02, 0.03],
        y: [-0.02, 0.02],
        n: [11, 9],
    };
    let line = MirrorLine {
        angle_deg: 90.0,
        point: [0.005, 0.0],
    };
    let nx = grid.n[0];
    for mu in [0.2, 0.45] {
        let (worst, scale) = mirror_mismatch(
            (&motion, &line.mirror(&motion)),
            &grid,
            mu,
            (|ix, iy| iy * nx + (nx - 1 - ix), [-1.0, 1.0]),
        );
        assert!(worst <= 1e-3 * scale, "μ {mu}: {worst:e} of {scale:e}");
    }
}

fn sweep(schedule: &Schedule, values: &[f64]) -> Vec<FrictionRow> {
    let target = schedule.target_spec.clone().unwrap();
    let sampled = target.sample().unwrap();
    let frictions: Vec<Friction> = values.iter().map(|&m| Friction::uniform(m)).collect();
    friction_sweep(&schedule.settings, &frictions, &|settings| {
        judge_check(&target, &sampled, schedule, settings)
    })
    .unwrap()
}

fn worst(rows: &[FrictionRow]) -> (f64, f64) {
    rows.iter().fold((0.0_f64, f64::INFINITY), |(e, s), r| {
        (
            e.max(r.realised_shape_error.unwrap()),
            s.min(r.realised_strength.unwrap()),
        )
    })
}

/// The committed synthesized sink (designed for μ 0.3) and the limits it
/// was played within.
fn synthesized_sink() -> (Schedule, ShakerLimits) {
    let s = Schedule::load(std::path::Path::new(
        "results/synthesized/sink/schedule.json",
    ))
    .unwrap();
    let limits = ShakerLimits::from_spec(s.played.as_ref().unwrap().limits.as_ref());
    (s, limits)
}

/// The issue's sink goal, from the committed synthesized sink (designed
/// for μ 0.3): alone its judge leaves more than 6 % shape error over the
/// range (7.3 % at its worst); its mirror-image time-share holds worst
/// shape ≤ 6 % at worst strength ≥ 0.4 s⁻¹ over μ ∈ [0.2, 0.4] (the
/// judge), within the shaker peaks the motion had. About 6 s of CPU:
/// `cargo test --release --lib design::mirror::robust_tests -- --ignored synthesized_sink`; the
/// default run holds a mirror share over friction on the family's ellipse
/// (`studies/tests/robust_family.rs`).
#[test]
#[ignore = "about 6 s of CPU: cargo test --release --lib design::mirror::robust_tests -- --ignored synthesized_sink"]
fn the_mirror_share_of_the_synthesized_sink_holds_over_friction() {
    let (synthesized, limits) = synthesized_sink();
    let line = MirrorLine::through_centre(0.0);
    let share = mirror_share(&synthesized, &limits, &line, MIRROR_SEGMENT_CYCLES).unwrap();
    assert_eq!(share.segments.len(), 2);
    let mu = [0.2, 0.25, 0.3, 0.35, 0.4];
    let (alone, _) = worst(&sweep(&synthesized, &mu));
    let (shape, strength) = worst(&sweep(&share, &mu));
    assert!(alone > 0.06, "the synthesized sink alone: {alone}");
    assert!(
        shape <= 0.06 && strength >= 0.4,
        "mirror share: {shape} at {strength}"
    );
    let peaks = crate::schedule::export::schedule_peaks(&share);
    let allowed = [limits.linear, limits.angular].concat();
    for (p, a) in peaks.iter().zip(&allowed) {
        assert!(*p <= a * (1.0 + 1e-9), "peak {p} over the limit {a}");
    }
}

/// `target` designed by `method` with `opts`, no progress output.
fn designed(
    target: &Target,
    opts: &crate::design::DesignOptions,
    method: crate::design::Method,
) -> crate::design::method::MethodDesign {
    let synth = crate::synth::SynthOptions {
        progress: crate::synth::progress::ProgressMode::Quiet,
        ..opts.synthesis
    };
    crate::inverse::run(target, &opts.by_method(method, &synth))
        .and_then(|o| o.into_method())
        .unwrap()
}

/// Quiet design options without a basis cache (synthesis needs none).
fn quiet() -> crate::design::DesignOptions {
    crate::design::DesignOptions {
        runtime: crate::work::Runtime::QUIET,
        ..crate::design::DesignOptions::default()
    }
}

/// The member `name` of the seeded random family (seed 45, 40 targets).
fn family_member(name: &str) -> Target {
    crate::request::family::family(45, 40)
        .into_iter()
        .find(|t| t.name == name)
        .unwrap()
}

/// The one-motion synthesized design of `target` at its nominal friction
/// (no progress output, no basis cache: synthesis needs none).
fn synthesized(target: &Target) -> Schedule {
    let mut exact = target.clone();
    exact.friction = target
        .friction
        .map(|f| crate::scene::FrictionSpec::exact(f.nominal()));
    let md = designed(&exact, &quiet(), crate::design::Method::Synthesize);
    let mut schedule = md.kept().schedule.clone();
    schedule.target_spec = Some(target.clone());
    schedule
}

/// The counter-rotating share (`design::mirror::counter_share`) holds
/// targets that no reflection maps to itself over μ ∈ [0.2, 0.4], where
/// the motion alone does not. Alone the motion turns with friction;
/// shared with the motion synthesized for the target's mirror image and
/// mirrored back, its worst shape error over the range falls under
/// `bounds.1`, at ≥ 70 % of the motion's own worst strength (the ramps
/// and the cos Δ of the module docs), within its shaker peaks.
fn counter_share_holds(motion: Schedule, target: Target, bounds: (f64, f64)) {
    let mut motion = motion;
    motion.target_spec = Some(target.clone());
    assert_eq!(mirror_axis(&target, &target.sample().unwrap()), None);
    let limits = ShakerLimits::from_spec(motion.played.as_ref().unwrap().limits.as_ref());
    // The partner under the motion's own limits (`auto` synthesizes
    // within the sequenced schedule's peaks).
    let mut mirrored = target.mirrored_y();
    mirrored.shaker = motion.played.as_ref().unwrap().limits.clone();
    let partner = synthesized(&mirrored);
    let share = counter_share(&motion, &partner, &limits, MIRROR_SEGMENT_CYCLES).unwrap();
    assert_eq!(share.segments.len(), 2);
    let mu = [0.2, 0.25, 0.3, 0.35, 0.4];
    let (alone, alone_strength) = worst(&sweep(&motion, &mu));
    let (shape, strength) = worst(&sweep(&share, &mu));
    let name = &target.name;
    assert!(alone > bounds.0, "{name}: the motion alone {alone}");
    assert!(
        shape <= bounds.1,
        "{name}: counter share {shape} at {strength}"
    );
    assert!(
        strength >= 0.7 * alone_strength,
        "{name}: {strength} against {alone_strength}"
    );
    let peaks = crate::schedule::export::schedule_peaks(&share);
    let allowed = [limits.linear, limits.angular].concat();
    for (p, a) in peaks.iter().zip(&allowed) {
        assert!(
            *p <= a * (1.0 + 1e-9),
            "{name}: peak {p} over the limit {a}"
        );
    }
}

/// The committed whirlpool's motion (designed for μ 0.3): alone worst
/// 18.7 % over μ ∈ [0.2, 0.4]; its counter-rotating share ≤ 7 % (measured
/// 6.2 % at 0.373; the motion is at 6.0 % at its own friction already),
/// at 81 % of the motion's worst strength. The same for a target
/// synthesized in the test:
/// [`the_counter_share_holds_an_asymmetric_target_over_friction`].
#[test]
fn the_counter_share_holds_the_whirlpool_over_friction() {
    let whirlpool =
        Schedule::load(std::path::Path::new("results/whirlpool/schedule.json")).unwrap();
    let mut target = whirlpool.target_spec.clone().unwrap();
    target.friction = Some(crate::scene::FrictionSpec::range(0.2, 0.4));
    counter_share_holds(whirlpool, target, (0.12, 0.07));
}

/// For generality, a line sink off the centre at 20° plus an off-centre
/// whirlpool, under the committed whirlpool's limits (a weaker in-plane
/// drive than the envelope's turns more with friction: δ = asin(μg/A)),
/// its motion synthesized in the test: alone worst 16.8 %, its
/// counter-rotating share ≤ 6.5 % (measured 5.6 % at 0.315) at 77 % of
/// the motion's worst strength. The default run keeps the committed
/// whirlpool ([`the_counter_share_holds_the_whirlpool_over_friction`]).
#[test]
#[ignore = "about 12 s of CPU: cargo test --release --lib design::mirror::robust_tests -- --ignored asymmetric"]
fn the_counter_share_holds_an_asymmetric_target_over_friction() {
    let whirlpool =
        Schedule::load(std::path::Path::new("results/whirlpool/schedule.json")).unwrap();
    let mut asymmetric = Target::from_json_str(
        r#"{"name": "asymmetric", "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]},
        "field": {"kind": "sum", "terms": [
            {"field": {"kind": "line_sink", "angle": 20, "offset": 0.005}},
            {"weight": 0.6, "field": {"kind": "whirlpool", "rotation": 0.5, "center": [0.01, -0.005]}}]},
        "friction": [0.2, 0.4]}"#,
    )
    .unwrap();
    asymmetric.shaker = whirlpool.played.as_ref().unwrap().limits.clone();
    counter_share_holds(synthesized(&asymmetric), asymmetric, (0.12, 0.065));
}

/// What bounds a whirlpool's share is the normal force's swing, not the
/// friction: the family's `whirlpool_2` (rotation −0.93, μ ∈ [0.217,
/// 0.431]) as the counter-rotating share (`--method mirror`) within the
/// envelope, whose contact margin 0.1 g lets the tilts swing N from 0.1 g
/// to 1.9 g at the region's corners, misses 6 % over the range (measured
/// 5.7–6.2 %, 0.5 percentage points from end to end: the share cancels
/// the turn); within the margin `auto` raises it to when nothing holds
/// (`design::method::gentle_limits`, 0.55 g: half the swing) it holds
/// ≤ 4 % (measured 1.9–2.6 %) at about half the strength (the margin's
/// cap ∝ 1 − m; measured 0.78 of 1.43 s⁻¹ at the weakest, 0.54).
/// The default run keeps the counter-rotating share over friction
/// ([`the_counter_share_holds_the_whirlpool_over_friction`]).
#[test]
#[ignore = "about 25 s of CPU: cargo test --release --lib design::mirror::robust_tests -- --ignored halving"]
fn halving_the_normal_force_swing_holds_the_whirlpool_over_friction() {
    let target = family_member("whirlpool_2");
    let worst_of = |margin: Option<f64>| {
        let mut t = target.clone();
        t.shaker = margin.map(|m| crate::request::ShakerSpec {
            contact_margin: Some(m),
            ..Default::default()
        });
        let md = designed(&t, &quiet(), crate::design::Method::Mirror);
        worst(&md.sensitivity.expect("judged over the range").rows)
    };
    let gentle = crate::design::method::gentle_limits(&ShakerLimits::envelope());
    let (shape, strength) = worst_of(None);
    let (g_shape, g_strength) = worst_of(Some(gentle.contact_margin));
    eprintln!("envelope {shape:.4} at {strength:.4}; gentle {g_shape:.4} at {g_strength:.4}");
    assert!(shape > 0.05, "within the envelope: {shape}");
    assert!(
        g_shape <= 0.04 && g_shape <= shape - 0.02,
        "within the wider margin: {g_shape} against {shape}"
    );
    let ratio = g_strength / strength;
    assert!((0.4..=0.7).contains(&ratio), "strength ratio {ratio}");
}

/// `auto` over a range adds syntheses when no default candidate holds the
/// target within 6 %: on the random family's `whirlpool_2` (rotation
/// −0.93, μ ∈ [0.217, 0.431]) every candidate within the envelope is over
/// 6 % (measured: the counter-rotating share 6.22 %, the motion alone
/// 9.94 %, the sequenced schedule 13.1 %); the synthesis and its shares
/// within the sequenced peaks are judged next (6.13 %, 16.6 %), then
/// (when those do not hold it either, or hold it weaker than half the
/// first synthesis) the synthesis and its shares within the wider contact
/// margin (2.57 %, 5.69 %), and the worst-case synthesis exactly when
/// none of them holds it. The kept one holds 6 % if any candidate does,
/// and is otherwise within the choice rule's 1 percentage point of the
/// best. About 1 min CPU: `cargo test --release --lib design::mirror::robust_tests -- --ignored`.
#[test]
#[ignore]
fn auto_over_a_range_adds_syntheses_when_nothing_holds() {
    let target = family_member("whirlpool_2");
    let cache = std::env::temp_dir().join(format!("platefield-robust-{}", std::process::id()));
    let opts = crate::design::DesignOptions::cached_quiet(&cache);
    let md = designed(&target, &opts, crate::design::Method::Auto);
    let _ = std::fs::remove_dir_all(&cache);
    let worst = |c: &crate::design::method::Candidate| {
        c.sensitivity
            .as_ref()
            .and_then(|s| s.worst_shape_error())
            .unwrap_or(f64::INFINITY)
    };
    use crate::design::method::Variant;
    let of = |v: Variant| md.candidates.iter().filter(move |c| c.variant == v);
    assert!(of(Variant::First).all(|c| worst(c) > 0.06));
    assert!(of(Variant::SequencedPeaks).count() >= 1);
    let peaks_hold = of(Variant::SequencedPeaks).any(|c| worst(c) <= 0.06);
    assert!(of(Variant::Gentle).count() >= 1);
    let gentle_holds = of(Variant::Gentle).any(|c| worst(c) <= 0.06);
    assert_eq!(
        of(Variant::WorstCase).count() == 1,
        !peaks_hold && !gentle_holds
    );
    let best = md
        .candidates
        .iter()
        .map(worst)
        .fold(f64::INFINITY, f64::min);
    let kept = worst(md.kept());
    let bound = if best <= 0.06 { 0.06 } else { best + 0.01 };
    assert!(kept <= bound, "kept {kept} against {best}");
}

/// A share's segment length is the caller's: each of the two segments
/// lasts `cycles` cycles, so the period grows with it; a length that
/// leaves no steady cycle between the two ramps is refused naming
/// `cycles`.
#[test]
fn a_share_lasts_the_cycles_asked_and_refuses_no_steady_cycle() {
    let (synthesized, limits) = synthesized_sink();
    let line = MirrorLine::through_centre(0.0);
    let period = |cycles| {
        let share = mirror_share(&synthesized, &limits, &line, cycles).unwrap();
        assert!(share.segments.iter().all(|s| s.cycles == cycles));
        share.period_s
    };
    let (short, long) = (period(12), period(2 * 12));
    assert!((long / short - 2.0).abs() < 1e-9, "{short} s, {long} s");
    let err = mirror_share(&synthesized, &limits, &line, 8).unwrap_err();
    assert!(err.to_string().contains("cycles"), "{err}");
}
