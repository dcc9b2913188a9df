//! Part classes: parts whose friction differs, told apart by their own
//! residuals.
//!
//! Each part's residual is first computed alone over the μ lattice
//! ([`super::estimate::scan`]); its minimum is the part's own estimate.
//! Sorted by that estimate, the parts are split in two where the split
//! lowers the summed residual most: the least residual of the two groups,
//! each at its own best μ of the lattice, against the least of the whole
//! group at one μ. The split stands when it lowers the residual by more
//! than [`SPLIT`] times σ̂² (a Δχ² far above what noise and the model's
//! part-to-part error give, and far below what parts of two frictions
//! give: ten parts at μ 0.2 against ten at 0.45 give above 10⁴) and the
//! two groups' μ differ by at least [`MIN_GAP`]; each group is split again
//! the same way. Each class is then fitted as one
//! ([`super::estimate::fit_class`]).

/// Δχ² a split must gain.
pub const SPLIT: f64 = 200.0;

/// Smallest difference in μ between two classes.
pub const MIN_GAP: f64 = 0.05;

/// The class of each part, classes numbered from 0 by increasing μ, from
/// each part's residual `curves[i][m]` over the lattice `mus` (non-finite
/// where the field could not be followed), its own estimate `own[i]` and
/// the residual variance `sigma2` (m²).
///
/// ```
/// use platefield::calibrate::classes::cluster;
/// let mus = [0.1, 0.2, 0.3, 0.4, 0.5];
/// // Parabolas about 0.2 and 0.4, of curvature 1e-2 m² per unit μ².
/// let part = |c: f64| mus.iter().map(|m| 1e-4 + 1e-2 * (m - c) * (m - c)).collect::<Vec<f64>>();
/// let curves = vec![part(0.2), part(0.4), part(0.21), part(0.41)];
/// let own = [0.2, 0.4, 0.21, 0.41];
/// assert_eq!(cluster(&curves, &mus, &own, 1e-8), vec![0, 1, 0, 1]);
/// assert_eq!(cluster(&curves[..1], &mus, &own[..1], 1e-8), vec![0]);
/// ```
pub fn cluster(curves: &[Vec<f64>], mus: &[f64], own: &[f64], sigma2: f64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..curves.len()).collect();
    order.sort_by(|&a, &b| own[a].total_cmp(&own[b]).then(a.cmp(&b)));
    let mut groups = Vec::new();
    split(&order, curves, mus, sigma2, &mut groups);
    let mut class = vec![0; curves.len()];
    for (c, g) in groups.iter().enumerate() {
        for &i in g {
            class[i] = c;
        }
    }
    class
}

/// The least summed residual of `group` at one μ of the lattice, and that μ.
fn least(group: &[usize], curves: &[Vec<f64>], mus: &[f64]) -> (f64, f64) {
    (0..mus.len())
        .map(|m| (group.iter().map(|&i| curves[i][m]).sum::<f64>(), mus[m]))
        .filter(|(v, _)| v.is_finite())
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or((f64::INFINITY, f64::NAN))
}

/// Splits `group` (sorted by μ) recursively, appending the classes in
/// increasing μ to `out`.
fn split(
    group: &[usize],
    curves: &[Vec<f64>],
    mus: &[f64],
    sigma2: f64,
    out: &mut Vec<Vec<usize>>,
) {
    let (whole, _) = least(group, curves, mus);
    let best = (1..group.len())
        .map(|k| {
            let (l, r) = (
                least(&group[..k], curves, mus),
                least(&group[k..], curves, mus),
            );
            (whole - l.0 - r.0, k, (r.1 - l.1).abs())
        })
        .filter(|c| c.0.is_finite() && c.2 >= MIN_GAP)
        .max_by(|a, b| a.0.total_cmp(&b.0));
    match best {
        Some((gain, k, _)) if gain > SPLIT * sigma2 => {
            split(&group[..k], curves, mus, sigma2, out);
            split(&group[k..], curves, mus, sigma2, out);
        }
        _ => out.push(group.to_vec()),
    }
}
