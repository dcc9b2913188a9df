//! A second start for targets with uniform transport: the in-plane
//! second-harmonic ratchet.
//!
//! In the closed-form seed ([`super::seed`]) the uniform part b of a target
//! (transport, a line off the centre) comes from vertical translation only,
//! v = (W/g)(Q_z, P_z), which a small a_z limit caps: with the sequenced
//! squeeze_trans's limits (a_z ≤ 0.109 m/s², T = 0.0301 s) it is 6.0e-4 m/s,
//! a seed strength of 0.060 s⁻¹. A second harmonic on an in-plane axis
//! makes the slip direction turn non-uniformly over the cycle, so ⟨ê⟩ ≠ 0
//! and friction drifts the part uniformly — a mechanism the averaged
//! analysis does not model. A harmonic 2 on x of about the seed circle's
//! own acceleration drifts parts an order of magnitude faster than the a_z
//! mechanism, in a direction that turns with the harmonic's phase
//! (measured: `platefield study probes`, `results/probes.md`).
//!
//! [`transport_start`] scans that harmonic on each in-plane axis with room
//! left under its limit (amplitudes `AMPLITUDES` of the room, phases in
//! steps of 360°/`PHASES`), simulating the steady drift of the seed's
//! translation plus the harmonic at the plate centre (tilts off, N = g
//! there), and keeps the one that carries the target's b at the greatest
//! strength k_T = (d·b̂)/|b| with the drift across b̂ at most
//! `ACROSS` of it. The start is the seed with its tilts rescaled to
//! strength k = min(k_T, k_tilt) (k_tilt: the tilts' peak limits and the
//! contact margin, checked kinematically over the region) plus that
//! harmonic, at the smallest scanned amplitude whose k_T reaches k.

use super::contact::kinematic_least_normal;
use super::limits::ShakerLimits;
use super::objective::{Evaluation, Objective};
use super::params::Coefficients;
use super::seed::Seed;
use crate::field::{FieldSettings, Grid};
use crate::motion::Motion;

/// Scanned amplitudes, as fractions of an axis's room (limit − harmonic 1).
pub(crate) const AMPLITUDES: [f64; 5] = [0.2, 0.4, 0.6, 0.8, 1.0];
/// Scanned phases per turn.
pub(crate) const PHASES: usize = 24;
/// Largest drift across the target's transport direction (fraction of the
/// drift along it).
pub(crate) const ACROSS: f64 = 0.1;

/// Axes of the in-plane translation and of the tilts.
const IN_PLANE: [usize; 2] = [0, 1];
const TILTS: [usize; 2] = [3, 4];

/// The transport start for `seed` under `limits` over `region`, with its
/// predicted strength; `None` when the target has no uniform part, the
/// limits allow one harmonic only, no in-plane axis has room, or no scanned
/// harmonic carries b.
pub fn transport_start(
    seed: &Seed,
    limits: &ShakerLimits,
    region: &Grid,
    settings: &FieldSettings,
) -> Option<(Coefficients, f64)> {
    let b = seed.fit.b;
    let bn = b[0].hypot(b[1]);
    // b below 1e-6 of the gradient's speed over the region is round-off of
    // the affine fit (a centred sink, saddle or whirlpool).
    let m = seed.fit.m;
    let extent = (region.x[1] - region.x[0]).hypot(region.y[1] - region.y[0]);
    let gradient = m.iter().flatten().fold(0.0_f64, |a, v| a.max(v.abs())) * extent;
    if limits.harmonics < 2 || bn <= 1e-6 * gradient || seed.strength <= 0.0 {
        return None;
    }
    let dir = [b[0] / bn, b[1] / bn];
    let lim = limits.axes();
    let c0 = &seed.coefficients;
    // The translation alone (tilts and a_z off) for the drift probe.
    let mut translation = Coefficients::zero(c0.period, limits.harmonics);
    for a in IN_PLANE {
        translation.c[a][0] = c0.c[a][0];
    }
    let mut best: Option<(f64, usize, f64, f64)> = None; // (k_T, axis, amplitude, phase)
    for axis in IN_PLANE {
        let h1 = c0.c[axis][0];
        let room = lim[axis] - h1[0].hypot(h1[1]);
        if room <= 1e-9 * lim[axis] {
            continue;
        }
        for frac in AMPLITUDES {
            for k in 0..PHASES {
                let phase = 2.0 * std::f64::consts::PI * k as f64 / PHASES as f64;
                let mut c = translation.clone();
                c.set(axis, 2, frac * room, phase);
                let m = Motion::Signals(c.to_signals());
                let sim = settings.simulator(&m);
                let Ok(s) = sim.steady_state([0.0, 0.0]) else {
                    continue;
                };
                let d = s.velocity;
                let along = d[0] * dir[0] + d[1] * dir[1];
                let across = (d[1] * dir[0] - d[0] * dir[1]).abs();
                if along <= 0.0 || across > ACROSS * along {
                    continue;
                }
                let kt = along / bn;
                if best.is_none_or(|b| kt > b.0) {
                    best = Some((kt, axis, frac * room, phase));
                }
            }
        }
    }
    let (kt, axis, amplitude, phase) = best?;
    // The tilts' own cap: peak limits, then the contact margin.
    let mut k = kt;
    for a in TILTS {
        let peak = c0.peak(a);
        if peak > 0.0 && lim[a] > 0.0 {
            k = k.min(seed.strength * lim[a] / peak);
        }
    }
    let h1 = c0.c[axis][0];
    let room_axis = lim[axis] - h1[0].hypot(h1[1]);
    let build = |k: f64, amplitude: f64| {
        let mut c = c0.clone();
        for a in TILTS {
            for cs in &mut c.c[a] {
                *cs = [cs[0] * k / seed.strength, cs[1] * k / seed.strength];
            }
        }
        c.set(axis, 2, amplitude.min(room_axis), phase);
        c
    };
    // The drift is nearly proportional to the harmonic's amplitude.
    let mut amplitude = amplitude * (k / kt).min(1.0);
    let g = settings.gravity;
    let room = (1.0 - limits.contact_margin) * g;
    for _ in 0..4 {
        let least = kinematic_least_normal(
            &Motion::Signals(build(k, amplitude).to_signals()),
            region,
            settings,
        );
        if least >= limits.contact_margin * g {
            break;
        }
        // N − g is linear in the tilts: scale onto the margin (with a
        // little to spare for a_z and the centripetal terms).
        k *= 0.99 * room / (g - least).max(1e-12);
    }
    // Balance: the tilts realise the gradient at some strength k_s (the
    // averaged analysis overestimates it); set the harmonic so that the
    // drift at the centre is k_s b. Steady states at the centre and at
    // ±q (q half-way to the region's corner): (v(q) − v(−q))/2 against M q.
    let q = [
        0.25 * (region.x[1] - region.x[0]),
        0.25 * (region.y[1] - region.y[0]),
    ];
    let mq = [
        m[0][0] * q[0] + m[0][1] * q[1],
        m[1][0] * q[0] + m[1][1] * q[1],
    ];
    let mq2 = mq[0] * mq[0] + mq[1] * mq[1];
    let mut ks = k;
    for _ in 0..3 {
        let motion = Motion::Signals(build(k, amplitude).to_signals());
        let sim = settings.simulator(&motion);
        let c = [
            0.5 * (region.x[0] + region.x[1]),
            0.5 * (region.y[0] + region.y[1]),
        ];
        let (Ok(v0), Ok(vp), Ok(vm)) = (
            sim.steady_state(c),
            sim.steady_state([c[0] + q[0], c[1] + q[1]]),
            sim.steady_state([c[0] - q[0], c[1] - q[1]]),
        ) else {
            break;
        };
        if mq2 > 0.0 {
            let g = [
                0.5 * (vp.velocity[0] - vm.velocity[0]),
                0.5 * (vp.velocity[1] - vm.velocity[1]),
            ];
            ks = (g[0] * mq[0] + g[1] * mq[1]) / mq2;
        }
        // The uniform part at the centre: v(c) − k_s M c.
        let mc = [
            m[0][0] * c[0] + m[0][1] * c[1],
            m[1][0] * c[0] + m[1][1] * c[1],
        ];
        let along = (v0.velocity[0] - ks * mc[0]) * dir[0] + (v0.velocity[1] - ks * mc[1]) * dir[1];
        if along <= 0.0 || ks <= 0.0 {
            break;
        }
        amplitude *= ks * bn / along;
    }
    (ks > seed.strength).then(|| (build(k, amplitude), ks))
}

/// Scales tried by [`scale_search`].
pub(crate) const SCALES: [f64; 4] = [0.85, 0.7, 0.55, 0.4];

/// A line search on the transport start's strength: its tilts and in-plane
/// harmonics ≥ 2 scaled by each of [`SCALES`] (the ratchet's drift and the
/// tilts' gradient shrink together, and the shape error the coupling of
/// the two leaves falls with them: on squeeze_trans, by more than half
/// at half scale); returns the best evaluation by the cost,
/// `start` included.
pub(crate) fn scale_search(objective: &Objective<'_>, start: &Evaluation) -> Evaluation {
    let c = objective.motion(&start.params).0;
    let mut best = start.clone();
    for f in SCALES {
        if objective.spent() {
            break;
        }
        let mut s = c.clone();
        for a in TILTS {
            for cs in &mut s.c[a] {
                *cs = [cs[0] * f, cs[1] * f];
            }
        }
        for a in IN_PLANE {
            for cs in s.c[a].iter_mut().skip(1) {
                *cs = [cs[0] * f, cs[1] * f];
            }
        }
        let e = objective.evaluate(&objective.layout().to_vec(&s));
        if e.cost < best.cost {
            best = e;
        }
    }
    best
}
