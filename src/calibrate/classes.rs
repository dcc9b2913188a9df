//! Part classes: parts whose friction differs, told apart by their own
//! estimates and those estimates' own uncertainties.
//!
//! Each part's residual is first computed alone over the μ lattice
//! (`super::estimate::scan`); the parabola through its minimum gives
//! the part's own estimate μ_i and standard error s_i. A part whose own
//! fit is **undetermined** (its minimum at the lattice's end, no positive
//! curvature, or s_i > [`MIN_GAP`]: it cannot tell two classes [`MIN_GAP`]
//! apart even at one standard error; a part resting where the field
//! vanishes, near a sink's centre) forms no class: it joins the class
//! whose estimate is nearest its own, and is left out of that class's fit.
//!
//! The determined parts, sorted by μ_i, are split in two where the two
//! groups' estimates differ most significantly: each group's estimate is
//! the inverse-variance mean m = Σ w_i μ_i / Σ w_i (w_i = 1/s_i²), its
//! variance s² = B/Σ w_i, widened by the group's own scatter (the Birge
//! ratio B = max(1, χ²/(n − 1)), χ² = Σ w_i (μ_i − m)²: parts of one
//! friction whose estimates scatter beyond their standard errors, by the
//! model's part-to-part error, widen their group's uncertainty rather
//! than split it). The split stands when z = |m₂ − m₁| / √(s₁² + s₂²)
//! exceeds [`Z_SPLIT`] and the two estimates differ by at least
//! [`MIN_GAP`]; each group is split again the same way. Each class is then
//! fitted as one (`super::estimate::fit_class`).

/// Significance a split must reach, in standard errors of the difference
/// of the two groups' estimates (far beyond the largest of the ~n
/// differences tested by chance, about 3 standard errors for 20 parts).
pub const Z_SPLIT: f64 = 5.0;

/// Smallest difference in μ between two classes, and the largest standard
/// error of a part's own estimate that still determines it.
pub const MIN_GAP: f64 = 0.05;

/// A part's own estimate: μ and its standard error (`None`: at the
/// lattice's end or without positive curvature).
pub type Own = (f64, Option<f64>);

/// Whether a part's own fit determines its μ well enough to place it
/// among classes (see the module's doc).
pub(crate) fn determined(own: &Own) -> bool {
    own.0.is_finite()
        && own
            .1
            .is_some_and(|s| s.is_finite() && s > 0.0 && s <= MIN_GAP)
}

/// The class of each part and whether it is fitted with its class (false:
/// undetermined, joined to the nearest class), classes numbered from 0
/// by increasing μ, from each part's own estimate. With no determined
/// part, every part is one class, fitted.
pub(crate) fn cluster(own: &[Own]) -> Vec<(usize, bool)> {
    let mut order: Vec<usize> = (0..own.len()).filter(|&i| determined(&own[i])).collect();
    if order.is_empty() {
        return vec![(0, true); own.len()];
    }
    order.sort_by(|&a, &b| own[a].0.total_cmp(&own[b].0).then(a.cmp(&b)));
    let mut groups = Vec::new();
    split(&order, own, &mut groups);
    let means: Vec<f64> = groups.iter().map(|g| pooled(g, own).0).collect();
    let mut class = vec![(0, false); own.len()];
    for (c, g) in groups.iter().enumerate() {
        for &i in g {
            class[i] = (c, true);
        }
    }
    for (i, o) in own.iter().enumerate() {
        if !determined(o) {
            let nearest = (0..means.len())
                .min_by(|&a, &b| (means[a] - o.0).abs().total_cmp(&(means[b] - o.0).abs()))
                .unwrap_or(0);
            class[i] = (nearest, false);
        }
    }
    class
}

/// A group's inverse-variance mean and its variance widened by the Birge
/// ratio (its parts all determined).
pub(crate) fn pooled(group: &[usize], own: &[Own]) -> (f64, f64) {
    let w = |i: usize| own[i].1.map_or(0.0, |s| 1.0 / (s * s));
    let sw: f64 = group.iter().map(|&i| w(i)).sum();
    let m = group.iter().map(|&i| w(i) * own[i].0).sum::<f64>() / sw;
    let chi2: f64 = group.iter().map(|&i| w(i) * (own[i].0 - m).powi(2)).sum();
    let birge = if group.len() > 1 {
        (chi2 / (group.len() - 1) as f64).max(1.0)
    } else {
        1.0
    };
    (m, birge / sw)
}

/// Splits `group` (determined parts sorted by μ) recursively, appending
/// the classes in increasing μ to `out`.
fn split(group: &[usize], own: &[Own], out: &mut Vec<Vec<usize>>) {
    let best = (1..group.len())
        .filter_map(|k| {
            let (l, r) = (pooled(&group[..k], own), pooled(&group[k..], own));
            let gap = (r.0 - l.0).abs();
            let z = gap / (l.1 + r.1).sqrt();
            (z.is_finite() && gap >= MIN_GAP).then_some((z, k))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0));
    match best {
        Some((z, k)) if z > Z_SPLIT => {
            split(&group[..k], own, out);
            split(&group[k..], own, out);
        }
        _ => out.push(group.to_vec()),
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `calibrate::classes::cluster`.
    #[test]
    fn example_cluster() {
        use crate::calibrate::classes::cluster;
        // Two frictions, 0.2 and 0.4, each part within its standard error.
        let own = [
            (0.2, Some(0.003)),
            (0.4, Some(0.004)),
            (0.205, Some(0.003)),
            (0.395, Some(0.004)),
        ];
        assert_eq!(
            cluster(&own),
            vec![(0, true), (1, true), (0, true), (1, true)]
        );
        // One friction whose parts scatter beyond their errors, and a part at
        // the lattice's end (undetermined): one class, that part unfitted.
        let own = [
            (0.25, Some(0.02)),
            (0.32, Some(0.03)),
            (0.37, Some(0.04)),
            (1.0, None),
        ];
        assert_eq!(
            cluster(&own),
            vec![(0, true), (0, true), (0, true), (0, false)]
        );
    }
}
