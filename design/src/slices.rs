//! How the points of each slice (the points at one level of a factor) share the 1/m-ths
//! of a column, m the slice's size: the table both the cell re-dealing
//! (`balance::untangle`) and the value swaps (`exchange::exchange`) keep up to date, so a
//! slice stays stratified (one point in each of its 1/m-ths) where it is.

/// The factors' slices: the level of each point, and the number of levels.
pub type Slices<'a> = [(&'a [usize], usize)];

/// For one column of n cells, the number of points of each slice in each of the slice's
/// blocks (its 1/m-ths of the cells).
#[derive(Debug, Clone)]
pub struct SliceCounts<'a> {
    slices: &'a Slices<'a>,
    /// The size of each slice: `sizes[f][level]`.
    sizes: Vec<Vec<usize>>,
    n: usize,
    /// `counts[f][level][block]`.
    counts: Vec<Vec<Vec<u32>>>,
}

impl<'a> SliceCounts<'a> {
    /// The counts of n points whose cells in the column are `cell(i)`.
    pub fn new(slices: &'a Slices<'a>, n: usize, cell: impl Fn(usize) -> usize) -> Self {
        let sizes: Vec<Vec<usize>> = slices
            .iter()
            .map(|&(labels, l)| {
                let mut m = vec![0usize; l];
                for &k in labels {
                    m[k] += 1;
                }
                m
            })
            .collect();
        let counts = sizes
            .iter()
            .map(|m| m.iter().map(|&mk| vec![0u32; mk.max(1)]).collect())
            .collect();
        let mut t = SliceCounts {
            slices,
            sizes,
            n,
            counts,
        };
        for i in 0..n {
            for f in 0..slices.len() {
                let (l, b) = (t.level(f, i), t.block(f, i, cell(i)));
                t.counts[f][l][b] += 1;
            }
        }
        t
    }

    /// The number of factors.
    pub fn factors(&self) -> usize {
        self.slices.len()
    }

    /// Point i's level of factor f.
    pub fn level(&self, f: usize, i: usize) -> usize {
        self.slices[f].0[i]
    }

    /// The block of cell c in point i's slice of factor f.
    pub fn block(&self, f: usize, i: usize, c: usize) -> usize {
        c * self.sizes[f][self.level(f, i)] / self.n
    }

    /// The points of point i's slice of factor f in the block of cell c.
    pub fn count(&self, f: usize, i: usize, c: usize) -> u32 {
        self.counts[f][self.level(f, i)][self.block(f, i, c)]
    }

    /// Whether point i in cell c shares a block of its slice with another point, in any
    /// factor.
    pub fn crowded(&self, i: usize, c: usize) -> bool {
        (0..self.factors()).any(|f| self.count(f, i, c) > 1)
    }

    /// Moves point i's count of factor f from the block of cell `from` to that of `to`;
    /// returns the change of the points in excess of one per block.
    pub fn shift(&mut self, f: usize, i: usize, from: usize, to: usize) -> i64 {
        let (l, from, to) = (
            self.level(f, i),
            self.block(f, i, from),
            self.block(f, i, to),
        );
        if from == to {
            return 0;
        }
        let c = &mut self.counts[f][l];
        let mut delta = -i64::from(c[from] > 1);
        c[from] -= 1;
        delta += i64::from(c[to] >= 1);
        c[to] += 1;
        delta
    }
}
