//! Candidate playing orders of a schedule's segments.
//!
//! What a segment realises depends on the segment before it (the part is
//! still moving the way the previous segment pushed it), so the order
//! changes the realised field. Measured on the Sink from four LineSinks at
//! one cycle each (`design --closed-loop`, error parts relative to the
//! promised field): the design's order 0°→180°→270°→90° plays each axis's
//! two LineSinks (whose mean tilts are opposite) one after the other, one
//! after a perpendicular segment and one after its twin, and has an 18 %
//! offset and a 7 % anisotropy; the cyclic order 0°→90°→180°→270°, in which
//! every segment follows a perpendicular one, has the four-fold symmetry of
//! the target and no offset, but its rotation sense gives a 2 % swirl; the
//! **mirrored** order 0°→90°→180°→270°→0°→270°→180°→90° (the cyclic order
//! followed by its reverse, every segment played twice per schedule period
//! with its own cycles) has both symmetries, and its shape-only error is
//! 0.9 % against 3.7 % and 27 %.
//!
//! Candidates for n segments, as index sequences into the segments:
//! * every cyclic order (the first segment fixed, the others permuted:
//!   (n − 1)! orders) when n ≤ [`MAX_PERMUTED`], else the design's order
//!   and its reverse;
//! * the mirrored order σ followed by (σ₀, σ_{n−1}, …, σ₁) for each cyclic
//!   order σ up to reversal (n ≥ 3; for n ≤ 2 it would repeat σ).
//!
//! The first candidate is always the design's order.

/// Most segments whose cyclic orders are all tried ((n − 1)! ≤ 24).
pub const MAX_PERMUTED: usize = 5;

/// One candidate order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Order {
    /// Indices into the segments, in playing order (a segment may appear
    /// twice in a mirrored order).
    pub sequence: Vec<usize>,
    /// True for a mirrored order.
    pub mirrored: bool,
}

/// All permutations of `items` in lexicographic order of positions.
fn permutations(items: &[usize]) -> Vec<Vec<usize>> {
    if items.len() <= 1 {
        return vec![items.to_vec()];
    }
    let mut out = Vec::new();
    for (i, &first) in items.iter().enumerate() {
        let mut rest = items.to_vec();
        rest.remove(i);
        for mut tail in permutations(&rest) {
            tail.insert(0, first);
            out.push(tail);
        }
    }
    out
}

/// The mirrored order of a cyclic order σ: σ, then σ₀ and the rest of σ reversed.
pub fn mirrored(sigma: &[usize]) -> Vec<usize> {
    let mut out = sigma.to_vec();
    if let Some((&first, rest)) = sigma.split_first() {
        out.push(first);
        out.extend(rest.iter().rev());
    }
    out
}

/// The candidate orders of `n` segments (see the module documentation).
pub fn candidates(n: usize) -> Vec<Order> {
    if n == 0 {
        return Vec::new();
    }
    let identity: Vec<usize> = (0..n).collect();
    let cyclic: Vec<Vec<usize>> = if n <= MAX_PERMUTED {
        permutations(&identity[1..])
            .into_iter()
            .map(|tail| [vec![0], tail].concat())
            .collect()
    } else {
        let rev = mirrored(&identity)[n..].to_vec();
        vec![identity.clone(), rev]
    };
    let mut out: Vec<Order> = cyclic
        .iter()
        .map(|s| Order {
            sequence: s.clone(),
            mirrored: false,
        })
        .collect();
    if n >= 3 {
        for s in &cyclic {
            // σ and its reverse give the same mirrored order, shifted.
            if s[1] > s[n - 1] {
                continue;
            }
            out.push(Order {
                sequence: mirrored(s),
                mirrored: true,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_first_candidate() {
        // n = 4: 3! = 6 cyclic orders, 3 mirrored ones.
        let c = candidates(4);
        assert_eq!(c.len(), 9);
        assert_eq!(c[0].sequence, vec![0, 1, 2, 3]);
        assert_eq!(c.iter().filter(|o| o.mirrored).count(), 3);
        assert!(c.contains(&Order {
            sequence: vec![0, 1, 2, 3, 0, 3, 2, 1],
            mirrored: true
        }));
        // Distinct, and every cyclic order starts with segment 0.
        for (i, a) in c.iter().enumerate() {
            assert_eq!(a.sequence[0], 0);
            for b in &c[i + 1..] {
                assert_ne!(a, b);
            }
        }
        // n ≤ 2: one cyclic order, and mirroring only repeats it.
        assert_eq!(candidates(1).len(), 1);
        assert_eq!(candidates(2).len(), 1);
        assert_eq!(candidates(3).len(), 2 + 1);
        assert_eq!(candidates(5).len(), 24 + 12);
        // Beyond MAX_PERMUTED: the design's order, its reverse, their mirror.
        let big = candidates(7);
        assert_eq!(big.len(), 3);
        assert_eq!(big[1].sequence, vec![0, 6, 5, 4, 3, 2, 1]);
    }

    #[test]
    fn mirrored_order_has_both_turn_senses() {
        // Every segment appears twice, and the joins of the second half are
        // those of the first, reversed: (a→b) in the first half pairs with
        // (b→a) in the second.
        let m = mirrored(&[0, 1, 2, 3]);
        let n = m.len();
        let joins: Vec<(usize, usize)> = (0..n).map(|i| (m[i], m[(i + 1) % n])).collect();
        for &(a, b) in &joins {
            assert!(joins.contains(&(b, a)), "{joins:?}");
        }
    }
}
