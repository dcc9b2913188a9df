//! Part classes: parts whose friction differs, told apart by their own
//! estimates.
//!
//! Each part's μ is first estimated alone (its residual over the μ
//! lattice, [`super::estimate::scan`], minimised by a parabola). Sorted by
//! μ, the parts are split wherever two neighbours differ by more than
//! [`SEPARATION`] combined standard errors and by at least [`MIN_GAP`]:
//! parts of one friction differ by their noise, about one combined
//! standard error, and a split needs four. Each class is then fitted as
//! one ([`super::estimate::fit_class`]).

/// Combined standard errors between two neighbours that split a class.
pub const SEPARATION: f64 = 4.0;

/// Smallest difference in μ between two classes.
pub const MIN_GAP: f64 = 0.03;

/// The class of each estimate `(μ, standard error)`, classes numbered
/// from 0 by increasing μ. An estimate without a standard error (at the
/// end of the lattice) counts as one of 0.
///
/// ```
/// use platefield::calibrate::cluster;
/// let parts = [(0.2, 0.004), (0.45, 0.004), (0.205, 0.004), (0.44, 0.005)];
/// assert_eq!(cluster(&parts), vec![0, 1, 0, 1]);
/// assert_eq!(cluster(&[(0.3, 0.01), (0.31, 0.01)]), vec![0, 0]);
/// ```
pub fn cluster(estimates: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..estimates.len()).collect();
    order.sort_by(|&a, &b| estimates[a].0.total_cmp(&estimates[b].0).then(a.cmp(&b)));
    let mut class = vec![0; estimates.len()];
    let mut current = 0;
    for w in order.windows(2) {
        let (a, b) = (estimates[w[0]], estimates[w[1]]);
        let gap = b.0 - a.0;
        if gap > MIN_GAP && gap > SEPARATION * a.1.hypot(b.1) {
            current += 1;
        }
        class[w[1]] = current;
    }
    class
}
