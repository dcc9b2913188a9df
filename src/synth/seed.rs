//! The closed-form seed of an affine target (the derivation is in the
//! [module documentation](super)): circular in-plane translation at the
//! translation limit, plus harmonic-1 tilts about x and y and vertical
//! translation whose in-phase and quadrature parts are the entries of the
//! target's affine map.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Matrix3, Vector3};

use super::limits::ShakerLimits;
use super::params::Coefficients;
use crate::dynamics::Friction;
use crate::error::{Error, Result};
use crate::field::Grid;
use crate::request::FieldSpec;

/// Signal indices (see [`super::params::AXIS_NAMES`]).
const LIN_X: usize = 0;
const LIN_Y: usize = 1;
const LIN_Z: usize = 2;
const ANG_X: usize = 3;
const ANG_Y: usize = 4;

/// Least-squares affine fit `f(q) ≈ M q + b` of a target over a grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AffineFit {
    /// `m[i][j]` = ∂f_i/∂q_j (1/s).
    pub m: [[f64; 2]; 2],
    /// `b` = f(0) (m/s).
    pub b: [f64; 2],
    /// ‖f − (M q + b)‖ / ‖f‖ over the grid: the part of the target no
    /// affine field reaches (0 for affine targets).
    pub residual: f64,
}

impl AffineFit {
    /// Fits `field` over the points of `grid` (equal weights).
    pub fn of(field: &FieldSpec, grid: &Grid) -> AffineFit {
        let pts = grid.points();
        let mut ata = Matrix3::zeros();
        let mut atf = [Vector3::zeros(); 2];
        let vals: Vec<[f64; 2]> = pts.iter().map(|p| field.eval(*p)).collect();
        for (p, f) in pts.iter().zip(&vals) {
            let row = Vector3::new(p[0], p[1], 1.0);
            ata += row * row.transpose();
            for i in 0..2 {
                atf[i] += row * f[i];
            }
        }
        // A 1-point or 1-row grid leaves the affine map underdetermined:
        // the pseudo-inverse picks the least-norm solution.
        // A pseudo-inverse is an SVD: only of a finite matrix (see
        // `crate::linalg`).
        let inv = Some(ata)
            .filter(|m| crate::linalg::all_finite(m.iter()))
            .and_then(|m| m.pseudo_inverse(1e-12 * m.norm()).ok())
            .unwrap_or(Matrix3::zeros());
        let sol = [inv * atf[0], inv * atf[1]];
        let m = [[sol[0][0], sol[0][1]], [sol[1][0], sol[1][1]]];
        let b = [sol[0][2], sol[1][2]];
        let (mut err, mut norm) = (0.0, 0.0);
        for (p, f) in pts.iter().zip(&vals) {
            for i in 0..2 {
                let a = m[i][0] * p[0] + m[i][1] * p[1] + b[i];
                err += (f[i] - a).powi(2);
                norm += f[i] * f[i];
            }
        }
        AffineFit {
            m,
            b,
            residual: if norm > 0.0 { (err / norm).sqrt() } else { 0.0 },
        }
    }
}

/// The averaged-friction model of a circular-translation motion: what it
/// predicts for the force and velocity fields.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AveragedCircle {
    /// Translation amplitude A (m/s²), counter-clockwise circle.
    pub translation: f64,
    /// Lead δ = asin(μ_k g / A) of the slip direction over the plate
    /// velocity (rad).
    pub lead: f64,
    /// Slip speed W = (A/ω) cos δ (m/s).
    pub slip_speed: f64,
    /// Phase ε of the slip direction ê = (cos(ωt + ε), sin(ωt + ε)).
    pub epsilon: f64,
    /// μ_k.
    pub mu: f64,
    /// g (m/s²).
    pub gravity: f64,
}

impl AveragedCircle {
    /// The model for translation amplitude `a` (> μ_k g) at `period`.
    pub(crate) fn new(a: f64, period: f64, friction: Friction, gravity: f64) -> AveragedCircle {
        let omega = 2.0 * PI / period;
        let mu = friction.kinetic;
        let lead = (mu * gravity / a).clamp(-1.0, 1.0).asin();
        AveragedCircle {
            translation: a,
            lead,
            slip_speed: a / omega * lead.cos(),
            // Plate velocity of the translation below turns as
            // (cos(ωt − π/2), sin(ωt − π/2)); the slip direction leads it by δ.
            epsilon: lead - FRAC_PI_2,
            mu,
            gravity,
        }
    }

    /// The circular translation: a_x = A sin(ωt + π/2), a_y = A sin(ωt).
    pub(crate) fn set_translation(&self, c: &mut Coefficients) {
        c.set(LIN_X, 1, self.translation, FRAC_PI_2);
        c.set(LIN_Y, 1, self.translation, 0.0);
    }

    /// (P, Q) of harmonic 1 of signal `axis` in the basis
    /// P sin(ωt + ε) + Q cos(ωt + ε).
    fn pq(&self, c: &Coefficients, axis: usize) -> [f64; 2] {
        let [cc, ss] = c.c[axis].first().copied().unwrap_or([0.0; 2]);
        let (se, ce) = self.epsilon.sin_cos();
        [cc * ce + ss * se, -cc * se + ss * ce]
    }

    /// (P, Q) of harmonic 1 of the normal force N(q) − g = a_z + α_x y − α_y x.
    fn normal_pq(&self, c: &Coefficients, q: [f64; 2]) -> [f64; 2] {
        let (z, ax, ay) = (self.pq(c, LIN_Z), self.pq(c, ANG_X), self.pq(c, ANG_Y));
        std::array::from_fn(|i| z[i] + ax[i] * q[1] - ay[i] * q[0])
    }

    /// Predicted mean friction force per unit mass while slipping,
    /// μ ⟨N ê⟩ = (μ/2)(Q_N, P_N) (m/s²).
    #[cfg(test)]
    pub(crate) fn force(&self, c: &Coefficients, q: [f64; 2]) -> [f64; 2] {
        let [p, qq] = self.normal_pq(c, q);
        [0.5 * self.mu * qq, 0.5 * self.mu * p]
    }

    /// Predicted steady drift velocity (W/g)(Q_N, P_N) (m/s).
    #[cfg(test)]
    pub(crate) fn velocity(&self, c: &Coefficients, q: [f64; 2]) -> [f64; 2] {
        let [p, qq] = self.normal_pq(c, q);
        let k = self.slip_speed / self.gravity;
        [k * qq, k * p]
    }
}

/// A closed-form starting motion for a target.
#[derive(Debug, Clone, PartialEq)]
pub struct Seed {
    /// The motion's coefficients (harmonic 1 only).
    pub coefficients: Coefficients,
    /// The averaged-friction model it was built with.
    pub(crate) model: AveragedCircle,
    /// The target's affine fit.
    pub fit: AffineFit,
    /// Predicted strength k: the seed's averaged field is k (M q + b) (for
    /// the parts of M, b whose axes are allowed).
    pub strength: f64,
    /// What limited the strength or could not be realised.
    pub notes: Vec<String>,
}

/// The closed-form seed for `field` over `region` under `limits`.
///
/// # Errors
/// The in-plane translation limit cannot make parts slip
/// (min(a_x, a_y) ≤ μ_s g), or no allowed axis realises any part of the
/// target (zero strength).
pub fn seed(
    field: &FieldSpec,
    region: &Grid,
    limits: &ShakerLimits,
    friction: Friction,
    gravity: f64,
) -> Result<Seed> {
    let fit = AffineFit::of(field, region);
    let a = limits.linear[0].min(limits.linear[1]);
    if a <= friction.stat * gravity {
        return Err(Error::invalid(
            "shaker.linear",
            format!(
                "the in-plane limits [{:.3}, {:.3}] m/s² cannot make parts slip: circular translation needs more than μ_s g = {:.3} m/s² on x and y",
                limits.linear[0],
                limits.linear[1],
                friction.stat * gravity
            ),
        ));
    }
    let model = AveragedCircle::new(a, limits.period, friction, gravity);
    let mut c = Coefficients::zero(limits.period, limits.harmonics);
    model.set_translation(&mut c);
    // Per unit strength: (P, Q) of α_x, α_y, a_z (derivation in the module docs).
    let u = gravity / model.slip_speed;
    let m = fit.m;
    let wanted = [
        (ANG_X, [m[1][1] * u, m[0][1] * u]),
        (ANG_Y, [-m[1][0] * u, -m[0][0] * u]),
        (LIN_Z, [fit.b[1] * u, fit.b[0] * u]),
    ];
    let lim = limits.axes();
    let mut strength = f64::INFINITY;
    let mut notes = Vec::new();
    let mut unit = Coefficients::zero(limits.period, limits.harmonics);
    // Parts below 1e-9 of the largest are round-off of the affine fit.
    let floor = 1e-9
        * wanted
            .iter()
            .map(|w| w.1[0].hypot(w.1[1]))
            .fold(0.0, f64::max);
    for (axis, [p, q]) in wanted {
        let r = p.hypot(q);
        if r <= floor {
            continue;
        }
        if lim[axis] <= 0.0 {
            notes.push(format!(
                "{} is needed (amplitude {r:.4} per unit strength) but its limit is 0: that part of the target is left out",
                super::params::AXIS_NAMES[axis]
            ));
            continue;
        }
        unit.set(axis, 1, r, model.epsilon + q.atan2(p));
        strength = strength.min(lim[axis] / r);
    }
    if !strength.is_finite() || strength <= 0.0 {
        return Err(Error::Unreachable(format!(
            "no allowed axis realises any part of the target (affine fit M = {:?}, b = {:?}); {}",
            fit.m,
            fit.b,
            notes.join("; ")
        )));
    }
    // Contact margin: |N − g| ≤ (1 − m) g at the region's corners (N − g
    // is affine in q, so its largest amplitude over the rectangle is at a
    // corner).
    let corners = [
        [region.x[0], region.y[0]],
        [region.x[1], region.y[0]],
        [region.x[0], region.y[1]],
        [region.x[1], region.y[1]],
    ];
    let swing = corners
        .iter()
        .map(|q| {
            let [p, qq] = model.normal_pq(&unit, *q);
            p.hypot(qq)
        })
        .fold(0.0, f64::max);
    let room = (1.0 - limits.contact_margin) * gravity;
    if swing * strength > room {
        notes.push(format!(
            "the contact margin {} g limits the strength to {:.4} (the peaks allow {strength:.4})",
            limits.contact_margin,
            room / swing
        ));
        strength = room / swing;
    }
    for axis in [ANG_X, ANG_Y, LIN_Z] {
        for cs in &mut unit.c[axis] {
            *cs = [cs[0] * strength, cs[1] * strength];
        }
        c.c[axis] = unit.c[axis].clone();
    }
    Ok(Seed {
        coefficients: c,
        model,
        fit,
        strength,
        notes,
    })
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    /// max over φ of |n_x| + |n_y| for n = (cos φ, sin φ) + extra(φ), on a
    /// grid of `n` values of φ (`n` a multiple of 8: the diagonals, where
    /// the first harmonic alone peaks, are on it).
    fn worst_l1(n: u32, extra: impl Fn(f64) -> [f64; 2]) -> f64 {
        (0..n)
            .map(|i| {
                let phi = 2.0 * PI * f64::from(i) / f64::from(n);
                let e = extra(phi);
                (phi.cos() + e[0]).abs() + (phi.sin() + e[1]).abs()
            })
            .fold(0.0, f64::max)
    }

    /// The corner cap of the module docs (`synth`): no constant or second
    /// harmonic added to a harmonic-1 normal-force gradient of unit
    /// amplitude brings max |n_x| + |n_y| below √2 (4096 pseudo-random
    /// ones, up to twice the first harmonic's amplitude; a grid of 2000
    /// angles holds the diagonals, and a coarser grid only lowers the
    /// maximum it finds), while a third harmonic of a sixth brings it to
    /// √(3/2) (20000 angles: its maximum is off the grid by less than
    /// 1e-6).
    #[test]
    fn two_harmonics_keep_the_corner_cap() {
        assert!((worst_l1(2000, |_| [0.0, 0.0]) - 2f64.sqrt()).abs() < 1e-6);
        let mut state: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..4096 {
            let k: [f64; 6] = std::array::from_fn(|_| next());
            let w = worst_l1(2000, |phi| {
                let (s2, c2) = (2.0 * phi).sin_cos();
                [k[0] + k[1] * c2 + k[2] * s2, k[3] + k[4] * c2 + k[5] * s2]
            });
            assert!(w >= 2f64.sqrt() - 1e-6, "{k:?}: {w}");
        }
        let c = 1.0 / 6.0;
        let w = worst_l1(20_000, |phi| {
            [c * (3.0 * phi).cos(), -c * (3.0 * phi).sin()]
        });
        assert!((w - 1.5f64.sqrt()).abs() < 1e-6, "{w} against √1.5");
    }
}
