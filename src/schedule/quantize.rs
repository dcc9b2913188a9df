//! Whole-cycle quantisation: time fractions become whole cycles per segment.
//!
//! A cycle is the quantum: segment i runs n_i whole periods T_i of its
//! primitive. For a total length N (given, or the shortest whose
//! quantisation error is within a tolerance), n_i = round(f_i N) with every
//! used segment at least `min_cycles` long. The quantisation error is
//! measured on the field, not the weights: ‖A(q − f)‖/‖A f‖ with q the
//! realised time fractions. Rest (the plate at rest is the zero field) takes
//! the remaining time in modes where Σf < 1.
//!
//! The default minimum of 10 cycles per segment comes from the interaction
//! errors in `results/verify/sink_interaction.md` (written by `platefield
//! study interaction`; a Sink from two orthogonal rest-to-rest LineSinks:
//! the error against the time-weighted prediction falls with the cycles
//! per segment, from half the field at one cycle to a few per cent at
//! 10).

/// Default minimum cycles per segment.
pub const DEFAULT_MIN_CYCLES: u32 = 10;
/// Default tolerance on the field's quantisation error.
pub const DEFAULT_QUANTIZATION_TOL: f64 = 0.02;
/// Longest schedule searched (cycles).
pub(crate) const MAX_TOTAL_CYCLES: u32 = 5000;

/// Result of quantising fractions.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Quantized {
    /// Cycles per column (0 = unused).
    pub cycles: Vec<u32>,
    /// Rest cycles (of period `rest_period`).
    pub rest_cycles: u32,
    /// Realised time fractions per column.
    pub fractions: Vec<f64>,
    /// Field quantisation error ‖A(q − f)‖/‖A f‖.
    pub error: f64,
}

/// Quantises `fractions` (one per column, Σ ≤ 1) for columns of periods
/// `periods`; `field_error(q)` returns ‖A(q − f)‖/‖A f‖ for realised
/// fractions q. Rest cycles use `rest_period`.
pub(crate) fn quantize(
    fractions: &[f64],
    periods: &[f64],
    rest_period: f64,
    min_cycles: u32,
    total: Option<u32>,
    tol: f64,
    field_error: &dyn Fn(&[f64]) -> f64,
) -> Quantized {
    let rest_fraction = (1.0 - fractions.iter().sum::<f64>()).max(0.0);
    let at = |n: u32| -> Quantized {
        let nf = f64::from(n);
        let mut cycles: Vec<u32> = fractions.iter().map(|f| (f * nf).round() as u32).collect();
        for (c, f) in cycles.iter_mut().zip(fractions) {
            if *c > 0 && *c < min_cycles {
                // Round up to the minimum or drop, whichever is nearer.
                *c = if f * nf >= 0.5 * f64::from(min_cycles) {
                    min_cycles
                } else {
                    0
                };
            }
        }
        let rest_cycles = (rest_fraction * nf).round() as u32;
        let time: Vec<f64> = cycles
            .iter()
            .zip(periods)
            .map(|(c, t)| f64::from(*c) * t)
            .collect();
        let total_time = time.iter().sum::<f64>() + f64::from(rest_cycles) * rest_period;
        let q: Vec<f64> = if total_time > 0.0 {
            time.iter().map(|t| t / total_time).collect()
        } else {
            vec![0.0; fractions.len()]
        };
        let error = field_error(&q);
        Quantized {
            cycles,
            rest_cycles,
            fractions: q,
            error,
        }
    };
    if let Some(n) = total {
        return at(n.max(1));
    }
    let mut best: Option<Quantized> = None;
    for n in 1..=MAX_TOTAL_CYCLES {
        let q = at(n);
        if q.cycles.iter().all(|c| *c == 0) {
            continue;
        }
        if q.error <= tol {
            return q;
        }
        if best.as_ref().is_none_or(|b| q.error < b.error) {
            best = Some(q);
        }
    }
    best.unwrap_or_else(|| at(MAX_TOTAL_CYCLES))
}
