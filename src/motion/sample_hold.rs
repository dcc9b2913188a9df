//! Export samples whose sample-and-hold integration is exact.
//!
//! A shaker controller holds each acceleration sample for Δt and loops the
//! file. Sample k is therefore the **mean** acceleration over its interval,
//!
//! ```text
//! a_k = (v(t_{k+1}) − v(t_k)) / Δt
//! ```
//!
//! from the analytic plate-centre velocity v (linear, and the world angular
//! velocity ω = J(θ)θ′ of the orientation exp(\[θ\]×), `super::rotation`),
//! so the held velocity equals v at every sample time to round-off,
//! whatever the waveform. The linear pose the controller integrates,
//! x_{k+1} = x_k + v_k Δt + a_k Δt²/2 = x_k + (v_k + v_{k+1}) Δt/2, is the
//! trapezoidal rule of v: exact over a whole period for a Fourier series
//! with fewer harmonics than samples per period (the trapezoidal rule is
//! exact for trigonometric polynomials of lower degree), and exponentially
//! accurate for smooth periodic v. Periods and segment joins fall on sample
//! boundaries: a period holds N = round(rate · T) samples, Δt = T/N, and the
//! **effective rate** N/T is reported. The orientation the controller
//! composes from the held angular samples (`super::Held`) follows
//! exp(\[θ\]×) to the same order: per hold the rotation's increment is
//! the trapezoidal rule of ω plus the Magnus term (Δt³/12) α × ω, off by
//! O((ωΔt)²) of the rotation's rates, which accumulates over many cycles
//! as a slow coning drift of order (ωΔt)²/6 of the motion's coning rate
//! (`tests/unit/convention.rs` measures it on every shipped design).
//!
//! **Ramps for six-signal motions.** A six-signal motion has zero-mean
//! velocity and pose only from its own initial state, not from rest. The
//! ramped export plays the pose x(t) = w(t) x_ss(t) (x_ss the steady
//! plate-centre pose, linear and angular) with a window w that rises from 0
//! to 1 over R cycles, stays 1 for the steady cycles and falls back to 0
//! over R cycles: the quintic smoothstep w = 10s³ − 15s⁴ + 6s⁵ of
//! s = t/(R T) (and its mirror). w, w′ and w″ vanish at both ends of a ramp,
//! so velocity w′x + w v and acceleration w″x + 2w′v + w a start from rest
//! at the home pose, join the steady motion continuously (C²) and end at
//! rest at home. During a ramp the acceleration can exceed the steady peak
//! by at most about 2·max w′/ω + max w″/ω² of it (1.875/(πR) + 0.146/R²
//! for one harmonic: 6.1 % at the default R = 10); [`HoldSamples::peaks`]
//! reports the exported peaks.

use std::f64::consts::PI;
use std::fmt::Write as _;

use super::{rotate, rotation, smoothstep, Motion, Signals, V3};
use crate::error::{positive, Error, Result};
use crate::input::num;

/// Default ramp length (cycles).
pub const DEFAULT_RAMP_CYCLES: u32 = 10;
/// Default number of steady cycles.
pub const DEFAULT_STEADY_CYCLES: u32 = 20;
/// Most samples an export may hold.
pub(crate) const MAX_SAMPLES: usize = 50_000_000;

/// Plate-centre velocity and pose (linear then angular: [v_x, v_y, v_z,
/// ω_x, ω_y, ω_z] and [p_x, p_y, p_z, θ_x, θ_y, θ_z], ω the world angular
/// velocity and θ the rotation vector of the orientation exp(\[θ\]×)).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct CentreState {
    /// Velocity (m/s, rad/s).
    pub velocity: [f64; 6],
    /// Pose (m, rad).
    pub pose: [f64; 6],
}

/// Acceleration samples to hold for Δt each.
#[derive(Debug, Clone, PartialEq)]
pub struct HoldSamples {
    /// Hold time Δt (s).
    pub dt: f64,
    /// Effective rate 1/Δt (samples/s).
    pub rate: f64,
    /// Samples per period of the (first) motion.
    pub samples_per_period: usize,
    /// [a_x, a_y, a_z, α_x, α_y, α_z] per sample (m/s², rad/s²; α the
    /// angular acceleration about the world axes).
    pub samples: Vec<[f64; 6]>,
    /// The state the plate must be in when the first sample starts.
    pub(crate) start: CentreState,
}

impl HoldSamples {
    /// The samples taking the plate through velocities `v` at
    /// t_k = k Δt: sample k is (v_{k+1} − v_k)/Δt.
    fn from_velocities(v: &[[f64; 6]], dt: f64, per_period: usize, start: CentreState) -> Self {
        HoldSamples {
            dt,
            rate: 1.0 / dt,
            samples_per_period: per_period,
            samples: v
                .windows(2)
                .map(|w| std::array::from_fn(|i| (w[1][i] - w[0][i]) / dt))
                .collect(),
            start,
        }
    }

    /// Per-axis peak |sample|.
    pub fn peaks(&self) -> [f64; 6] {
        axis_extremes(&self.samples)
    }

    /// CSV with the columns of `platefield export` (t_s is the start of
    /// each hold interval).
    pub(crate) fn to_csv(&self) -> String {
        let mut csv = String::from(
            "t_s,ax_m_s2,ay_m_s2,az_m_s2,alpha_x_rad_s2,alpha_y_rad_s2,alpha_z_rad_s2\n",
        );
        for (k, a) in self.samples.iter().enumerate() {
            let _ = writeln!(
                csv,
                "{:.9},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e}",
                k as f64 * self.dt,
                a[0],
                a[1],
                a[2],
                a[3],
                a[4],
                a[5]
            );
        }
        csv
    }
}

/// Per axis the largest |value| over `rows` (six channels each).
pub(crate) fn axis_extremes(rows: &[[f64; 6]]) -> [f64; 6] {
    let mut p = [0.0_f64; 6];
    for r in rows {
        for (p, v) in p.iter_mut().zip(r) {
            *p = p.max(v.abs());
        }
    }
    p
}

/// Velocity and pose of the plate centre at time `t` (exact: the screw's
/// rotation is not linearised; a six-signal motion's are its zero-mean
/// antiderivatives, its angular velocity the world ω = J(θ)θ′ of
/// `super::rotation`).
pub(crate) fn centre_state(motion: &Motion, t: f64) -> CentreState {
    match motion {
        Motion::Signals(_) | Motion::Ramped(_) => world_angular(signal_state(motion, t)),
        m => signal_state(m, t),
    }
}

/// [`centre_state`] but with a six-signal motion's angular velocity the
/// rate θ′ of its rotation vector (the integral of its signals, which
/// design limits), not the world ω; the same for the other motions.
pub(crate) fn signal_state(motion: &Motion, t: f64) -> CentreState {
    match motion {
        Motion::Screw(s) => {
            let k = V3::from(s.axis).normalize();
            let psi = s.rotation.eval(t, s.period);
            let d = s.translation.eval(t, s.period);
            let h = V3::from(s.point);
            let rh = rotate(&h, &k, psi.q);
            let v = -(k * psi.dq).cross(&rh) + k * d.dq;
            let p = h - rh + k * d.q;
            let (w, th) = (k * psi.dq, k * psi.q);
            CentreState {
                velocity: [v.x, v.y, v.z, w.x, w.y, w.z],
                pose: [p.x, p.y, p.z, th.x, th.y, th.z],
            }
        }
        Motion::Signals(sig) => signals_state(sig, t),
        Motion::Ramped(r) => {
            let (pose, velocity) = r.centre_state(t);
            CentreState { velocity, pose }
        }
        Motion::Held(h) => h.centre_state_piece(t, t),
    }
}

/// `state` with its angular velocity θ′ replaced by the world angular
/// velocity ω = J(θ)θ′ of the orientation exp(\[θ\]×).
fn world_angular(mut state: CentreState) -> CentreState {
    let v3 = |x: &[f64; 6]| V3::new(x[3], x[4], x[5]);
    let (w, _) = rotation::world_rates(
        &v3(&state.pose),
        &v3(&state.velocity),
        &V3::zeros(),
        f64::sin_cos,
    );
    state.velocity[3..].copy_from_slice(w.as_slice());
    state
}

/// Zero-mean antiderivatives of every term `A sin(nωt + φ)`:
/// velocity −A/(nω) cos(nωt + φ), pose −A/(nω)² sin(nωt + φ).
fn signals_state(sig: &Signals, t: f64) -> CentreState {
    let mut out = CentreState::default();
    let w = 2.0 * PI / sig.period;
    let axes = [
        &sig.linear.x,
        &sig.linear.y,
        &sig.linear.z,
        &sig.angular.x,
        &sig.angular.y,
        &sig.angular.z,
    ];
    for (i, terms) in axes.into_iter().enumerate() {
        for term in terms {
            let wn = w * f64::from(term.harmonic);
            let (s, c) = (wn * t + term.phase).sin_cos();
            out.velocity[i] -= term.amplitude / wn * c;
            out.pose[i] -= term.amplitude / (wn * wn) * s;
        }
    }
    out
}

/// Samples per period N = round(rate · T) (≥ 2) and Δt = T/N.
fn grid(period: f64, rate: f64) -> Result<(usize, f64)> {
    positive("--rate", rate)?;
    let n = (rate * period).round();
    if n < 2.0 {
        return Err(Error::invalid(
            "--rate",
            format!(
                "{} Hz gives fewer than 2 samples per {} s period",
                num(rate),
                num(period)
            ),
        ));
    }
    if n > MAX_SAMPLES as f64 {
        return Err(Error::invalid(
            "--rate",
            format!(
                "{} Hz gives more than {MAX_SAMPLES} samples per period",
                num(rate)
            ),
        ));
    }
    Ok((n as usize, period / n))
}

/// One period of `motion`, to be looped: N = round(rate · T) samples. The
/// plate must start in [`HoldSamples::start`] (rest for the rest-to-rest
/// primitives; the steady state at t = 0 for a six-signal motion — use
/// [`ramped`] to get there from rest).
///
/// # Errors
/// A rate that is not positive or gives fewer than 2 or more than
/// `MAX_SAMPLES` samples per period.
pub(crate) fn periodic(motion: &Motion, rate: f64) -> Result<HoldSamples> {
    let period = motion.period();
    let (n, dt) = grid(period, rate)?;
    let start = centre_state(motion, 0.0);
    // v(t_N) is v(0) exactly: the loop closes to round-off.
    let v: Vec<[f64; 6]> = (0..n)
        .map(|k| centre_state(motion, k as f64 * dt).velocity)
        .chain(std::iter::once(start.velocity))
        .collect();
    Ok(HoldSamples::from_velocities(&v, dt, n, start))
}

/// A six-signal (or any periodic) motion from rest at home: `ramp` cycles
/// of ramp-in, `steady` cycles, `ramp` cycles of ramp-out, back to rest at
/// home (see the module docs). Looping the file repeats the whole sequence.
///
/// # Errors
/// As [`periodic`]; `ramp` must be ≥ 1.
pub(crate) fn ramped(motion: &Motion, rate: f64, ramp: u32, steady: u32) -> Result<HoldSamples> {
    if ramp == 0 {
        return Err(Error::invalid("--ramp-cycles", "must be ≥ 1"));
    }
    let period = motion.period();
    let (n, dt) = grid(period, rate)?;
    let cycles = 2 * ramp as usize + steady as usize;
    let total = n * cycles;
    if total > MAX_SAMPLES {
        return Err(Error::invalid(
            "--steady-cycles",
            format!("{cycles} cycles of {n} samples exceed {MAX_SAMPLES} samples"),
        ));
    }
    let ramp_len = n * ramp as usize;
    let ramp_time = period * f64::from(ramp);
    let v: Vec<[f64; 6]> = (0..=total)
        .map(|k| {
            // Window by sample index, so the ends are exact.
            let (w, dw) = if k < ramp_len {
                let [w, dw, _] = smoothstep(k as f64 / ramp_len as f64);
                (w, dw)
            } else if k + ramp_len > total {
                let [w, dw, _] = smoothstep((total - k) as f64 / ramp_len as f64);
                (w, -dw)
            } else {
                (1.0, 0.0)
            };
            let t = (k % n) as f64 * dt;
            let s = signal_state(motion, t);
            world_angular(CentreState {
                velocity: std::array::from_fn(|i| dw / ramp_time * s.pose[i] + w * s.velocity[i]),
                pose: s.pose.map(|x| w * x),
            })
            .velocity
        })
        .collect();
    Ok(HoldSamples::from_velocities(
        &v,
        dt,
        n,
        CentreState::default(),
    ))
}

/// One segment of a sequence: a motion played for `duration` seconds, or
/// rest.
#[derive(Debug, Clone, Copy)]
pub(crate) struct MotionSpan<'a> {
    /// The motion (`None`: rest).
    pub motion: Option<&'a Motion>,
    /// Duration (s).
    pub duration: f64,
}

/// A sequence of rest-to-rest segments (one schedule period, to be looped)
/// with every join on a sample boundary: Δt = T₀/round(rate · T₀), T₀ the
/// first motion's period. A motion segment must last a whole number of
/// samples (within 1e-9 of Δt) and start and end at rest; rest segments are
/// rounded to the nearest whole number of samples (at least one; a rest of
/// 0 s is left out).
///
/// # Errors
/// As [`periodic`]; a motion segment whose duration is not a whole number
/// of samples or that does not start and end at rest (names
/// `segments[i]`).
pub(crate) fn sequence(segments: &[MotionSpan<'_>], rate: f64) -> Result<HoldSamples> {
    let (n, dt, states) = sequence_states(segments, rate)?;
    let v: Vec<[f64; 6]> = states.iter().map(|s| s.velocity).collect();
    Ok(HoldSamples::from_velocities(
        &v,
        dt,
        n,
        CentreState::default(),
    ))
}

/// The plate-centre states at the sample times t_k = kΔt (k = 0 to the
/// last sample's end) of [`sequence`]'s grid, with its samples per period
/// N and Δt: the exact velocity and pose of each segment's motion at its
/// own time, rest at home between.
///
/// # Errors
/// As [`sequence`].
pub(crate) fn sequence_states(
    segments: &[MotionSpan<'_>],
    rate: f64,
) -> Result<(usize, f64, Vec<CentreState>)> {
    // The sample grid of the first motion; a rest-only sequence is held at
    // `rate` itself (all samples zero).
    let (n, dt) = match segments.iter().find_map(|s| s.motion) {
        Some(first) => grid(first.period(), rate)?,
        None => {
            positive("--rate", rate)?;
            (1, 1.0 / rate)
        }
    };
    let mut v: Vec<CentreState> = vec![CentreState::default()];
    for (i, seg) in segments.iter().enumerate() {
        // A rest of 0 s (which a schedule may hold) is no rest.
        if seg.motion.is_none() && seg.duration == 0.0 {
            continue;
        }
        positive(&format!("segments[{i}].duration_s"), seg.duration)?;
        let k = (seg.duration / dt).round().max(1.0) as usize;
        let Some(m) = seg.motion else {
            v.extend(std::iter::repeat_n(CentreState::default(), k));
            continue;
        };
        if (k as f64 * dt - seg.duration).abs() > 1e-9 * dt {
            return Err(Error::invalid(
                format!("segments[{i}].duration_s"),
                format!(
                    "{} s is not a whole number of {dt:.6e} s samples (rate {} Hz)",
                    seg.duration,
                    1.0 / dt
                ),
            ));
        }
        // Rest at the start and end of one cycle (the motion is periodic, so
        // at every whole-cycle join), to round-off relative to the cycle's
        // peak velocity: a large-amplitude Circle's residual is ~1e-13 rad/s.
        let peak = (0..64)
            .map(|j| centre_state(m, m.period() * f64::from(j) / 64.0).velocity)
            .flat_map(|v| v.into_iter().map(f64::abs))
            .fold(0.0, f64::max);
        let scale = 1e-9 * peak + m.period() * 1e-12;
        for t in [0.0, m.span()] {
            let s = centre_state(m, t);
            if s.velocity.iter().any(|x| x.abs() > scale) {
                return Err(Error::invalid(
                    format!("segments[{i}]"),
                    format!(
                        "the motion is not at rest at t = {t} s of the segment: export it with a ramp"
                    ),
                ));
            }
        }
        v.extend((1..=k).map(|j| centre_state(m, j as f64 * dt)));
        if v.len() > MAX_SAMPLES {
            return Err(Error::invalid(
                "--rate",
                format!("more than {MAX_SAMPLES} samples"),
            ));
        }
    }
    Ok((n, dt, v))
}

/// The controller: holds each sample for Δt, looping the file `loops`
/// times from `start`, and returns the state at the end of each loop
/// (x ← x + v Δt + a Δt²/2, v ← v + a Δt per linear axis; the angular
/// samples composed as a rotation, [`super::Held`]).
///
/// ```
/// use platefield::motion::sample_hold::{play, CentreState, HoldSamples};
///
/// let file = HoldSamples { dt: 0.1, rate: 10.0, samples_per_period: 2,
///     samples: vec![[1.0, 0.0, 0.0, 0.0, 0.0, 2.0], [-1.0, 0.0, 0.0, 0.0, 0.0, -2.0]],
///     start: CentreState::default() };
/// let ends = play(&file, CentreState::default(), 2);
/// assert!((ends[1].pose[0] - 0.02).abs() < 1e-15 && (ends[1].pose[5] - 0.04).abs() < 1e-15);
/// ```
#[cfg(test)]
pub(crate) fn play(samples: &HoldSamples, start: CentreState, loops: usize) -> Vec<CentreState> {
    let mut ends = Vec::with_capacity(loops);
    let mut state = start;
    for _ in 0..loops {
        let Ok(held) = super::Held::new(&HoldSamples {
            start: state,
            ..samples.clone()
        }) else {
            break;
        };
        state = held.state_at(held.len());
        ends.push(state);
    }
    ends
}
