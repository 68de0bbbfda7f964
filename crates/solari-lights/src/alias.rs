//! Walker/Vose alias table: O(1) sampling of a discrete distribution.

/// One slot of an [`AliasTable`]: keep this index with probability `threshold`, else take
/// `alias`. `#[repr(C)]` so a GPU twin can read the same layout later.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct AliasEntry {
    /// Probability of keeping the slot's own index.
    pub threshold: f32,
    /// The index taken otherwise.
    pub alias: u32,
}

/// A discrete distribution proportional to non-negative weights, sampled in constant time.
#[derive(Clone, Debug, Default)]
pub struct AliasTable {
    /// One entry per weight.
    pub entries: Vec<AliasEntry>,
    /// Each index's probability (weight / total).
    pub pmf: Vec<f32>,
}

impl AliasTable {
    /// Builds the table. Non-finite or negative weights count as zero; if every weight is zero
    /// the distribution is uniform (documented fallback, so callers never divide by zero).
    pub fn new(weights: &[f32]) -> Self {
        let n = weights.len();
        if n == 0 {
            return Self::default();
        }
        let clean: Vec<f64> = weights
            .iter()
            .map(|&w| {
                if w.is_finite() && w > 0.0 {
                    w as f64
                } else {
                    0.0
                }
            })
            .collect();
        let total: f64 = clean.iter().sum();
        let pmf64: Vec<f64> = if total > 0.0 && total.is_finite() {
            clean.iter().map(|w| w / total).collect()
        } else {
            vec![1.0 / n as f64; n]
        };
        // Vose's method on scaled probabilities (mean 1).
        let mut scaled: Vec<f64> = pmf64.iter().map(|p| p * n as f64).collect();
        let mut entries = vec![
            AliasEntry {
                threshold: 1.0,
                alias: 0,
            };
            n
        ];
        let (mut small, mut large): (Vec<usize>, Vec<usize>) =
            (0..n).partition(|&i| scaled[i] < 1.0);
        while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
            entries[s] = AliasEntry {
                threshold: scaled[s] as f32,
                alias: l as u32,
            };
            scaled[l] -= 1.0 - scaled[s];
            if scaled[l] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // Leftovers (rounding) keep themselves.
        for i in small.into_iter().chain(large) {
            entries[i] = AliasEntry {
                threshold: 1.0,
                alias: i as u32,
            };
        }
        Self {
            entries,
            pmf: pmf64.iter().map(|&p| p as f32).collect(),
        }
    }

    /// Number of outcomes.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether there are no outcomes.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Draws an index from two uniform numbers in \[0, 1). Panics on an empty table.
    pub fn sample(&self, u_slot: f32, u_keep: f32) -> usize {
        let n = self.entries.len();
        let slot = ((u_slot * n as f32) as usize).min(n - 1);
        let e = self.entries[slot];
        if u_keep < e.threshold {
            slot
        } else {
            e.alias as usize
        }
    }
}
