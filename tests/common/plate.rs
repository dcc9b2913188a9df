//! A rigid plate driven by an exported acceleration file, written from the
//! export header's convention alone (nothing from `platefield::motion`):
//! the linear channels are the centre's acceleration, integrated per world
//! axis; the angular channels are the angular acceleration α = dω/dt about
//! the world axes, ω the angular velocity in dR/dt = \[ω\]× R, so the
//! orientation quaternion obeys q′ = ½ (0, ω) ⊗ q. Each sample is held for
//! its interval: the linear state is advanced exactly (quadratic in τ), the
//! orientation by classical RK4 in `substeps` equal steps with
//! ω(τ) = ω₀ + ατ evaluated at each stage time.

// Each test that includes this file uses part of it.
#![allow(dead_code)]

/// A quaternion (w, x, y, z).
pub type Quat = [f64; 4];

/// `a ⊗ b`.
pub fn mul(a: &Quat, b: &Quat) -> Quat {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// The quaternion of the rotation vector `v` (angle |v| about v/|v|).
pub fn from_rotation_vector(v: &[f64; 3]) -> Quat {
    let angle = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if angle == 0.0 {
        return [1.0, 0.0, 0.0, 0.0];
    }
    let (s, c) = (angle / 2.0).sin_cos();
    let k = s / angle;
    [c, v[0] * k, v[1] * k, v[2] * k]
}

/// The angle (rad) of the rotation taking `a` to `b`.
pub fn angle_between(a: &Quat, b: &Quat) -> f64 {
    let conj = [a[0], -a[1], -a[2], -a[3]];
    let d = mul(&conj, b);
    let s = (d[1] * d[1] + d[2] * d[2] + d[3] * d[3]).sqrt();
    2.0 * s.atan2(d[0].abs())
}

/// The plate's state.
#[derive(Debug, Clone, Copy)]
pub struct Plate {
    /// Centre position (m).
    pub x: [f64; 3],
    /// Centre velocity (m/s).
    pub v: [f64; 3],
    /// Orientation.
    pub q: Quat,
    /// World angular velocity (rad/s).
    pub w: [f64; 3],
}

impl Plate {
    /// At rest in the home pose.
    pub fn rest() -> Plate {
        Plate {
            x: [0.0; 3],
            v: [0.0; 3],
            q: [1.0, 0.0, 0.0, 0.0],
            w: [0.0; 3],
        }
    }

    /// Holds the sample `a` (linear then angular) for `dt`.
    pub fn hold(&mut self, a: &[f64; 6], dt: f64, substeps: usize) {
        for ((x, v), a) in self.x.iter_mut().zip(&mut self.v).zip(a) {
            *x += *v * dt + 0.5 * a * dt * dt;
            *v += a * dt;
        }
        let h = dt / substeps as f64;
        let w0 = self.w;
        let omega =
            |t: f64| -> Quat { [0.0, w0[0] + a[3] * t, w0[1] + a[4] * t, w0[2] + a[5] * t] };
        let rate = |t: f64, q: &Quat| -> Quat { mul(&omega(t), q).map(|c| 0.5 * c) };
        let step =
            |q: &Quat, k: &Quat, f: f64| -> Quat { std::array::from_fn(|i| q[i] + f * k[i]) };
        let mut q = self.q;
        for s in 0..substeps {
            let t = s as f64 * h;
            let k1 = rate(t, &q);
            let k2 = rate(t + h / 2.0, &step(&q, &k1, h / 2.0));
            let k3 = rate(t + h / 2.0, &step(&q, &k2, h / 2.0));
            let k4 = rate(t + h, &step(&q, &k3, h));
            q = std::array::from_fn(|i| {
                q[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            });
            let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
            q = q.map(|c| c / n);
        }
        self.q = q;
        for (w, a) in self.w.iter_mut().zip(&a[3..]) {
            *w += a * dt;
        }
    }
}

/// The rows of an exported CSV (comment lines and the header skipped):
/// (Δt, samples).
pub fn read_export(csv: &str) -> (f64, Vec<[f64; 6]>) {
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let dt = rows[rows.len() - 1][0] / (rows.len() - 1) as f64;
    (
        dt,
        rows.iter()
            .map(|r| std::array::from_fn(|i| r[i + 1]))
            .collect(),
    )
}
