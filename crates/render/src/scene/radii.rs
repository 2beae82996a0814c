//! Node radii stored once when they are all equal ([`Radii`]).

/// The radius of every node of a [`super::Scene`]: one shared `f64` while every radius is the
/// same (tractography, polylines, `--radius`), a per-node list only once some radius differs
/// (SWC, thin-tube clamping). "Same" is bitwise, so every radius reads back exactly as set.
///
/// ```
/// use tubecast_render::scene::Radii;
/// let mut r = Radii::uniform(0.5);
/// r.push(0.5, 1); // a second node with the same radius: still nothing per node
/// assert_eq!((r.get(1), r.memory_bytes()), (0.5, 0));
/// r.set(0, 0.25, 2); // one differs: the list holds both
/// assert_eq!((r.get(0), r.get(1)), (0.25, 0.5));
/// assert!(r.memory_bytes() >= 16);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Radii {
    /// One radius per node, or empty when every node has `shared`.
    list: Vec<f64>,
    /// The radius of every node while `list` is empty.
    shared: f64,
}

impl Radii {
    /// Every node with radius `r`.
    pub fn uniform(r: f64) -> Self {
        Self { list: Vec::new(), shared: r }
    }

    /// One radius per node; stored once when they are all (bitwise) equal.
    pub fn from_vec(list: Vec<f64>) -> Self {
        match list.first() {
            Some(&r) if list.iter().any(|v| v.to_bits() != r.to_bits()) => Self { list, shared: r },
            first => Self::uniform(first.copied().unwrap_or(0.0)),
        }
    }

    /// Radius of node `i` (the shared one while no radius differs).
    #[inline]
    pub fn get(&self, i: usize) -> f64 {
        if self.list.is_empty() {
            self.shared
        } else {
            self.list[i]
        }
    }

    /// Whether one radius is stored for every node.
    pub fn is_uniform(&self) -> bool {
        self.list.is_empty()
    }

    /// Set node `i` of `n` nodes to `r`, keeping one per node once it differs.
    pub fn set(&mut self, i: usize, r: f64, n: usize) {
        if self.list.is_empty() {
            if r.to_bits() == self.shared.to_bits() {
                return;
            }
            self.list = vec![self.shared; n];
        }
        self.list[i] = r;
    }

    /// Append the radius of a new node after `n` nodes (the first node sets the shared one).
    pub fn push(&mut self, r: f64, n: usize) {
        if n == 0 {
            *self = Self::uniform(r);
        } else if self.list.is_empty() && r.to_bits() != self.shared.to_bits() {
            self.list = vec![self.shared; n];
        }
        if !self.list.is_empty() {
            self.list.push(r);
        }
    }

    /// Raise every radius of `n` nodes below `r` to `r`: (how many, how many were ≤ 0).
    pub fn raise(&mut self, r: f64, n: usize) -> (usize, usize) {
        if self.list.is_empty() {
            let low = self.shared < r;
            if low {
                let zero = self.shared <= 0.0;
                self.shared = r;
                return (n, if zero { n } else { 0 });
            }
            return (0, 0);
        }
        let (mut replaced, mut zero) = (0, 0);
        for v in self.list.iter_mut().filter(|v| **v < r) {
            (replaced, zero) = (replaced + 1, zero + (*v <= 0.0) as usize);
            *v = r;
        }
        (replaced, zero)
    }

    /// Bytes held by the per-node list (capacity; 0 while the radius is shared).
    pub fn memory_bytes(&self) -> usize {
        self.list.capacity() * std::mem::size_of::<f64>()
    }

    /// Release spare capacity.
    pub fn shrink_to_fit(&mut self) {
        self.list.shrink_to_fit();
    }
}
