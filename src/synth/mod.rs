//! Motion synthesis: one simultaneous six-signal plate motion designed for a
//! target field, seeded in closed form and refined by re-simulation.
//!
//! # Averaged-friction analysis (the seed)
//!
//! While the plate slips under a part, the friction force per unit mass on
//! the part is μ N ê, with N the normal force per unit mass (effective
//! gravity, [`crate::dynamics`]) and ê the direction of the plate's velocity
//! relative to the part. Over a cycle the part drifts with the mean of it,
//! μ⟨N ê⟩.
//!
//! **Circular translation.** Let the plate centre translate in a
//! counter-clockwise circle, a_x = A sin(ωt + π/2), a_y = A sin ωt
//! (velocity (A/ω)(cos(ωt − π/2), sin(ωt − π/2))). With N ≈ g the part,
//! unable to follow (A > μ_s g), settles on a circle of its own: writing
//! velocities as complex numbers, plate V e^{iωt} (V = A/ω) and part
//! U e^{iωt}, Newton's law iωU = μg (V − U)/|V − U| gives |U| = μg/ω and
//! U ⟂ V − U, so the slip direction ê rotates uniformly at ω, *leading* the
//! plate velocity by
//!
//! ```text
//! δ = asin(μ g / A),   slip speed W = |V − U| = (A/ω) cos δ,
//! ê(t) = (cos(ωt + ε), sin(ωt + ε)),   ε = δ − π/2.
//! ```
//!
//! **Normal-force harmonic.** For small angles the normal force at plate
//! point q = (x, y) is N = g + a_z + α_x y − α_y x (a_z the vertical
//! acceleration, α_x, α_y the angular accelerations; from
//! a_s = a_c + Ω' × r, [`crate::motion`]). Write the first harmonic of each
//! signal in the slip-direction basis, s(t) = P sin(ωt + ε) + Q cos(ωt + ε).
//! Then ⟨sin(ωt+ε) ê⟩ = (0, ½), ⟨cos(ωt+ε) ê⟩ = (½, 0), and
//!
//! ```text
//! μ⟨N ê⟩ = (μ/2) (Q_N(q), P_N(q)),   P_N = P_z + P_αx y − P_αy x  (same for Q)
//! ```
//!
//! (g and every other harmonic average out against ê). A small drift v_d
//! of the part adds the mean of −μg ∂ê/∂v_d = −μg (I − ê êᵀ)/W, whose
//! cycle average is −(μg/2W) I, so the steady drift velocity is
//!
//! ```text
//! v(q) = (W/g) (Q_N(q), P_N(q)).
//! ```
//!
//! **Every affine field has a closed-form seed.** v is affine in q, and its
//! four gradient entries and two offsets are six independent numbers:
//!
//! ```text
//! v = (W/g) [ −Q_αy  Q_αx ] q + (W/g) (Q_z, P_z)
//!           [ −P_αy  P_αx ]
//! ```
//!
//! so a target f(q) = M q + b (least-squares affine fit over the region,
//! [`seed::AffineFit`]) is realised with strength k by
//! (P, Q)_αx = k(g/W)(M₂₂, M₁₂), (P, Q)_αy = −k(g/W)(M₂₁, M₁₁),
//! (P, Q)_z = k(g/W)(b_y, b_x), each signal A_s sin(ωt + ε + atan2(Q, P))
//! with A_s = k (g/W) hypot(P, Q). That covers sink, source, saddle, line
//! sink at any angle and offset (a line off the centre has b ≠ 0, which
//! takes vertical translation a_z), whirlpool and scaled circle (the curl part
//! of M comes from the tilts' quadrature, not from rotation about z),
//! uniform transport (b alone: vertical translation) and their sums. The
//! strength k is the largest the per-axis peak limits and the contact
//! margin allow: N − g = a_z + α_x y − α_y x is affine in q, so its largest
//! amplitude over the rectangular region is at a corner and
//! |N − g| ≤ (1 − m) g there keeps N ≥ m g ([`seed::seed`]).
//!
//! **Why a second harmonic does not lift the margin's cap** (the saddle of
//! `results/synthesis.md` is margin-bound: its seed at 0.8005 of the
//! 1.1202 s⁻¹ its peaks allow).
//! With n(t) = (−α_y, α_x)(t) the gradient of N over the plate, the corners
//! (±d, ±d) keep the margin when |n_x(t)| + |n_y(t)| ≤ (1 − m) g / d at
//! every t. Only n's first harmonic enters the mean force, and for a sink
//! or a saddle it is A (cos φ, ± sin φ), φ = ωt + ε. At φ = π/4 and
//! φ = 5π/4 the first harmonic changes sign while a constant and every
//! even harmonic do not, so by the triangle inequality the L1 norms of n at
//! the two instants sum to at least 2√2 A: one of them is ≥ √2 A, exactly
//! the cap of harmonic 1 alone. A third harmonic could lower it — n_x =
//! A (cos φ + cos 3φ / 6), n_y = A (sin φ − sin 3φ / 6) has
//! max |n_x| + |n_y| = √(3/2) A ≈ 1.225 A (the best such c found by a scan
//! of c cos 3φ), 15 % more strength for the same margin — but the default
//! shaker's controller plays harmonics 1 and 2 only
//! (`seed::tests::two_harmonics_keep_the_corner_cap`
//! checks both statements numerically).
//!
//! *That proof assumes a uniformly turning ê* (circular translation), which
//! is what makes n's first harmonic circular. **A non-uniform ê does not
//! lift the cap either**, for three reasons:
//!
//! 1. The corner condition is on n alone: ê does not enter it. The mean
//!    force μ⟨(n·q) ê⟩ pairs n with ê harmonic by harmonic, so a tilt of
//!    harmonics 1 and 2 sees only ê's harmonics 1 and 2. An ê that dwells
//!    near the x and y axes (ê = (cos θ, sin θ), θ = φ + β sin 4φ) puts
//!    its extra content into harmonics 3, 5, … (e^{iθ} = Σ J_k(β)
//!    e^{i(1+4k)φ}), which such a tilt cannot use. The "C/2 instead of
//!    C/(2√2)" of a slip direction dwelling on the axes needs n itself to
//!    switch between the axes in step with it: bang-bang tilts, harmonics
//!    3, 5, … (the √(3/2) above is the first step of that).
//! 2. Through harmonic 1, no slip-direction pattern beats the uniform one.
//!    Let ê_x and ê_y have first harmonics of amplitudes r_x and r_y (any
//!    phases). A force gradient diag(k, −k) per μ (a saddle) needs
//!    ⟨n_x ê_x⟩ = k and ⟨n_y ê_y⟩ = −k, so n's first harmonic has
//!    amplitudes a ≥ 2k/r_x on x and b ≥ 2k/r_y on y; its largest L1 norm,
//!    √(a² + b² + 2ab |cos(phase difference)|), is at least
//!    2k √(1/r_x² + 1/r_y²). Parseval on |ê| ≤ 1 gives r_x² + r_y² ≤ 2,
//!    so 1/r_x² + 1/r_y² ≥ 4/(r_x² + r_y²) ≥ 2 and k ≤ C/(2√2),
//!    C = (1 − m) g / d: the uniform ê's cap. Non-uniformity only moves
//!    ê's content out of harmonic 1.
//! 3. What is left is the pairing of a tilt harmonic 2 with ê's harmonic
//!    2, which a translation with a harmonic 2 creates — together with a
//!    ratchet drift ⟨ê⟩ ≠ 0 ([`transport`]) a centred saddle must not have,
//!    and with less harmonic 1 under the same per-axis peak, so a smaller
//!    slip speed W and less drift per unit force (v ∝ W above).
//!
//! Measured by `margin_cap` (the simulator's linear response to each tilt
//! coefficient and a linear programme for the largest strength under the
//! peaks and the corner margin, all tilt harmonics free) on the saddle row's
//! limits (`platefield study probes`, `results/probes.md`): the circle's cap
//! is the closed form's and the tilts' harmonic 2 adds nothing; a
//! translation with a harmonic 2 of any share of the limit, on x, on y or
//! both and at any phase, and tilted ellipses, all cap below the circle,
//! and re-simulated at the margin the best of them is no stronger than the
//! circle. The saddle's margin cap stays
//! harmonic 1's for a shaker of harmonics 1 and 2
//! (`margin_cap::tests::second_harmonic_translation_does_not_lift_the_saddle_cap`).
//!
//! **What the seed leaves out**, corrected by refinement: the part's own
//! velocity modulation by N (the lead δ is for N = g), Coriolis, gravity
//! tilt and centripetal terms, and the part's drift across the cycle.
//! Under lab limits the seed's sink field comes out slightly weaker than
//! predicted and turned by several degrees; shifting the tilt phases by
//! that turn brings it close to the target, and refinement keeps it there
//! (measured: `tests/unit/synth.rs`, `seed_predicts_the_simulated_sink`,
//! `calibration_turns_the_seed_back`). Non-affine targets (jet, off-centre circle) get
//! their affine part only: they need higher harmonics, rotation about z or
//! a sequence of synthesized motions.
//!
//! # Refinement by re-simulation
//!
//! First the seed's phase is calibrated by re-simulation ([`calibrate`]):
//! its simulated field comes out turned by several degrees (the lead δ
//! above is that of a part under N = g), and shifting the normal-force
//! signals' phase by the simulated turn removes it without changing any
//! amplitude (so the peaks and the contact margin are the seed's), in one
//! step on the lab sink (`tests/unit/synth.rs`,
//! `calibration_turns_the_seed_back`). Then `least_squares` runs Levenberg–Marquardt
//! ([`levenberg`]) on the six signals' Fourier coefficients ([`params`])
//! from the calibrated seed: the residuals are the coarse grid's
//! re-simulated steady-state field against the target, the peaks and the
//! contact margin ([`objective`]), and the Jacobian's columns are one
//! parallel batch of re-simulations. A few steps reach what 300
//! Nelder–Mead evaluations do on the lab sink
//! (`results/design_speed.md`): the seed has already put the motion near
//! the target, and the kinks below are smoothed by the forward-difference
//! step (1 % of each axis limit). The alternative, kept for comparison
//! (`SynthOptions::lm` `None`): [`multistart`], argmin's Nelder–Mead from the
//! calibrated seed and from the seed itself. It needs no gradient: the
//! objective is a simulation with stick-slip events and validity switches
//! (piecewise smooth, kinks where a sample starts or stops sticking), the
//! dimension is small (8 for the lab's harmonic-1 x/y limits, 12·H at
//! most), and finite-difference gradients would cost 2n simulations per
//! step and be corrupted by the kinks; particle swarm needs far more
//! evaluations than the ≈ 10² the time budget allows.
//!
//! **Transport start.** Where the target has a uniform part and the limits
//! allow a second harmonic, [`transport::transport_start`] adds a start that
//! carries it by an in-plane second-harmonic ratchet instead of vertical
//! translation (which a sequenced schedule's limits cap near 0.1 m/s²),
//! balanced against the tilts' simulated gradient, phase-calibrated (with
//! or without `calibrate`, which is about the seed) and
//! line-searched in strength (`transport::scale_search`); the better of
//! it and the calibrated seed runs first. On squeeze_trans under its
//! sequenced limits it nearly triples the judged strength of the one-harmonic
//! motion (measured: `results/synthesis.md`, its squeeze_trans rows).

pub mod calibrate;
pub mod contact;
pub(crate) mod least_squares;
pub mod levenberg;
pub(crate) mod limits;
pub mod margin_cap;
pub mod multistart;
pub mod objective;
pub mod params;
pub mod progress;
pub mod robust;
pub mod seed;
pub mod stall;
mod synthesize;
pub mod transport;

pub use limits::ShakerLimits;
pub use synthesize::synthesize;
pub(crate) use synthesize::synthesize_classes;
pub(crate) use synthesize::Checked;
pub use synthesize::SynthOptions;
pub use synthesize::Synthesis;
pub use synthesize::{POLISH_LM, SYNTH_LM};

#[cfg(test)]
#[path = "../../tests/unit/synth.rs"]
mod synthesis_tests;
