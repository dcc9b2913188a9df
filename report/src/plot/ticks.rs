//! "Nice" axis ticks: 1-2-5 steps for linear axes, decades for log axes.

/// A tick step `mantissa × 10^exponent` with `mantissa` ∈ {1, 2, 5}.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct NiceStep {
    /// 1, 2 or 5.
    pub mantissa: u8,
    /// Power of ten.
    pub exponent: i32,
}

impl NiceStep {
    /// The smallest 1-2-5 step that is ≥ `raw` (roughly; values within
    /// ~1.5×, 3× and 7× of a power of ten round to 1, 2 and 5).
    ///
    /// `raw` must be positive and finite; anything else gives step 1.
    pub(crate) fn for_raw(raw: f64) -> NiceStep {
        if !(raw.is_finite() && raw > 0.0) {
            return NiceStep {
                mantissa: 1,
                exponent: 0,
            };
        }
        let mut exponent = raw.log10().floor() as i32;
        let norm = raw / 10f64.powi(exponent);
        let mantissa = if norm < 1.5 {
            1
        } else if norm < 3.0 {
            2
        } else if norm < 7.0 {
            5
        } else {
            exponent += 1;
            1
        };
        NiceStep { mantissa, exponent }
    }

    /// The step as a number.
    pub fn value(&self) -> f64 {
        self.multiple(1)
    }

    /// `k × step`, computed as the double nearest to the exact decimal
    /// value (so `3 × 0.1` is `0.3`, not `0.30000000000000004`).
    pub(crate) fn multiple(&self, k: i64) -> f64 {
        format!("{}e{}", k * self.mantissa as i64, self.exponent)
            .parse()
            .unwrap_or(f64::NAN)
    }

    /// Decimals needed to print multiples of this step exactly.
    pub fn decimals(&self) -> usize {
        (-self.exponent).max(0) as usize
    }

    /// Label for `k × step`: fixed decimals, or scientific notation (e.g.
    /// `2e-5`) when the step is below 1e-4 or the value is ≥ 1e6.
    pub fn label(&self, k: i64) -> String {
        let v = self.multiple(k);
        if k == 0 {
            return "0".to_string();
        }
        if self.exponent < -4 || v.abs() >= 1e6 {
            format!("{v:e}")
        } else {
            format!("{v:.*}", self.decimals())
        }
    }
}

/// Ticks of a linear axis: the step and the integer multiples `k` of it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Ticks {
    /// The step.
    pub step: NiceStep,
    /// Multiples of `step`, increasing; tick `i` is at `step.multiple(ks[i])`.
    pub ks: Vec<i64>,
}

impl Ticks {
    /// Tick positions.
    pub fn values(&self) -> Vec<f64> {
        self.ks.iter().map(|&k| self.step.multiple(k)).collect()
    }

    /// Tick labels (see [`NiceStep::label`]).
    pub fn labels(&self) -> Vec<String> {
        self.ks.iter().map(|&k| self.step.label(k)).collect()
    }
}

/// Ticks at the multiples of a 1-2-5 step that lie in `[lo, hi]`, aiming
/// for about `target` ticks (at least 2 intervals' worth of resolution).
///
/// Degenerate or non-finite input gives no ticks.
pub(crate) fn nice_ticks(lo: f64, hi: f64, target: usize) -> Ticks {
    let step = NiceStep::for_raw((hi - lo) / target.max(2) as f64);
    let s = step.value();
    if !(lo.is_finite() && hi.is_finite() && hi > lo && s > 0.0) {
        return Ticks { step, ks: vec![] };
    }
    let eps = 1e-9;
    let k0 = (lo / s - eps).ceil() as i64;
    let k1 = (hi / s + eps).floor() as i64;
    Ticks {
        step,
        ks: (k0..=k1).collect(),
    }
}

/// `[lo, hi]` widened outwards to multiples of the nice step chosen for
/// about `target` ticks, together with those ticks.
pub(crate) fn nice_range(lo: f64, hi: f64, target: usize) -> ([f64; 2], Ticks) {
    let step = NiceStep::for_raw((hi - lo) / target.max(2) as f64);
    let s = step.value();
    if !(lo.is_finite() && hi.is_finite() && hi > lo && s > 0.0) {
        return ([lo, hi], Ticks { step, ks: vec![] });
    }
    let eps = 1e-9;
    let k0 = (lo / s + eps).floor() as i64;
    let k1 = (hi / s - eps).ceil() as i64;
    let ticks = Ticks {
        step,
        ks: (k0..=k1).collect(),
    };
    ([step.multiple(k0), step.multiple(k1)], ticks)
}

/// Ticks of a log axis covering `[lo, hi]` (both > 0): returns the axis
/// range widened to whole decades, the labelled decade exponents (every
/// decade, or every 2nd/3rd/... when there are more than 8) and unlabelled
/// minor ticks at 2..9 × 10^k when the range spans at most 6 decades.
pub(crate) fn log_ticks(lo: f64, hi: f64) -> ([f64; 2], Vec<i32>, Vec<f64>) {
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && hi >= lo) {
        return ([1.0, 10.0], vec![0, 1], vec![]);
    }
    let e0 = (lo.log10() + 1e-9).floor() as i32;
    let mut e1 = (hi.log10() - 1e-9).ceil() as i32;
    if e1 <= e0 {
        e1 = e0 + 1;
    }
    let span = e1 - e0;
    let stride = (span + 7) / 8;
    let majors: Vec<i32> = (e0..=e1).filter(|e| (e - e0) % stride == 0).collect();
    let mut minors = Vec::new();
    if span <= 6 {
        for e in e0..e1 {
            for m in 2..=9 {
                minors.push(format!("{m}e{e}").parse().unwrap_or(f64::NAN));
            }
        }
    }
    let pow = |e: i32| format!("1e{e}").parse().unwrap_or(f64::NAN);
    ([pow(e0), pow(e1)], majors, minors)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn is_nice(step: f64) -> bool {
        let e = step.log10().floor();
        let m = step / 10f64.powf(e);
        [1.0, 2.0, 5.0].iter().any(|&n| (m - n).abs() < 1e-9)
    }

    #[test]
    fn ticks_on_0_to_005_are_nice() {
        let t = nice_ticks(0.0, 0.05, 5);
        let v = t.values();
        assert_eq!(v, vec![0.0, 0.01, 0.02, 0.03, 0.04, 0.05]);
        assert!(is_nice(t.step.value()));
        for x in &v {
            // Exactly the decimal value: at most 3 characters after "0.".
            assert!(format!("{x}").len() <= 4, "{x}");
            let k = x / t.step.value();
            assert!((k - k.round()).abs() < 1e-9);
        }
        assert_eq!(
            t.labels(),
            vec!["0", "0.01", "0.02", "0.03", "0.04", "0.05"]
        );
    }

    #[test]
    fn steps_are_1_2_5() {
        for (lo, hi) in [
            (0.0, 1.0),
            (-3.7, 12.2),
            (1e-6, 7e-6),
            (0.0, 0.3),
            (100.0, 1e5),
        ] {
            for n in [3, 5, 8] {
                let t = nice_ticks(lo, hi, n);
                assert!(is_nice(t.step.value()), "{lo} {hi} {n}");
                assert!(t.ks.len() >= 2, "{lo} {hi} {n}: {:?}", t.values());
                for v in t.values() {
                    assert!(v >= lo - 1e-12 && v <= hi + 1e-12);
                }
            }
        }
        assert_eq!(nice_ticks(0.0, 0.3, 3).values(), vec![0.0, 0.1, 0.2, 0.3]);
    }

    #[test]
    fn range_is_widened_to_ticks() {
        let ([a, b], t) = nice_range(0.013, 0.047, 4);
        assert_eq!((a, b), (0.01, 0.05));
        assert_eq!(t.values().first(), Some(&0.01));
        assert_eq!(t.values().last(), Some(&0.05));
    }

    #[test]
    fn labels_use_scientific_for_tiny_steps() {
        let t = nice_ticks(0.0, 1e-5, 5);
        assert_eq!(t.labels()[1], "2e-6");
    }

    #[test]
    fn log_ticks_are_decades() {
        let ([a, b], majors, minors) = log_ticks(3e-4, 0.5);
        assert_eq!((a, b), (1e-4, 1.0));
        assert_eq!(majors, vec![-4, -3, -2, -1, 0]);
        assert_eq!(minors.len(), 4 * 8);
        let (_, majors, minors) = log_ticks(1e-12, 1e3);
        assert!(majors.len() <= 9 && minors.is_empty());
        assert_eq!(log_ticks(10.0, 10.0).0, [10.0, 100.0]);
    }
}
