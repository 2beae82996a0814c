//! [`Links`]: a scene's links as node index pairs, chains stored implicitly.

use std::fmt;

/// A stretch of consecutive links stored one way.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Seg {
    /// Index of the stretch's first link.
    start: u32,
    /// A run: the first node (link `start + j` is `[at + j, at + j + 1]`); explicit pairs:
    /// the index in [`Links::pairs`] of the stretch's first link.
    at: u32,
    /// A run of chain links rather than explicit pairs.
    run: bool,
}

/// A scene's links, link `k` being the node index pair [`Links::get`]`(k)`, in the order they
/// were pushed. Runs of chain links `[i, i + 1], [i + 1, i + 2], …` (a streamline's links, an
/// unbranched SWC section listed parent first) are stored as one 12-byte entry however long
/// they are; the other links as explicit 8-byte pairs. A tractogram's links cost a few bytes
/// per streamline instead of 8 bytes per link. Equality compares the link lists.
///
/// ```
/// use tubecast_render::scene::Links;
/// let mut l = Links::default();
/// l.extend([[0, 1], [1, 2], [2, 3], [5, 3], [3, 3]]);
/// assert_eq!((l.len(), l.get(1), l.get(3)), (5, [1, 2], [5, 3]));
/// assert_eq!(l, vec![[0, 1], [1, 2], [2, 3], [5, 3], [3, 3]]);
/// assert_eq!(l.iter().nth(4), Some([3, 3]));
/// l.shrink_to_fit();
/// // One run (the first three links) and one stretch of two explicit pairs: 2·12 + 2·8 bytes.
/// assert_eq!((l.stretches(), l.memory_bytes()), (2, 2 * 12 + 2 * 8));
/// ```
#[derive(Clone, Default)]
pub struct Links {
    segs: Vec<Seg>,
    pairs: Vec<[u32; 2]>,
    len: usize,
}

impl Links {
    /// Number of links.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when there are no links.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Link `k` as its node index pair.
    ///
    /// Panics when `k ≥ len()`, as indexing a slice does.
    #[inline]
    pub fn get(&self, k: usize) -> [u32; 2] {
        assert!(k < self.len, "link {k} of {}", self.len);
        let s = self.segs[self.seg_of(k)];
        Self::of(s, &self.pairs, (k - s.start as usize) as u32)
    }

    /// Link `j` of stretch `s`.
    #[inline(always)]
    fn of(s: Seg, pairs: &[[u32; 2]], j: u32) -> [u32; 2] {
        match s.run {
            true => [s.at + j, s.at + j + 1],
            false => pairs[(s.at + j) as usize],
        }
    }

    /// The links in order.
    pub fn iter(&self) -> Iter<'_> {
        Iter { links: self, seg: 0, k: 0 }
    }

    /// The links from link `k` on, in order: [`Self::iter`] without its first `k` links, found
    /// as [`Self::get`] finds link `k` (one bisection at most, not one per link).
    ///
    /// ```
    /// use tubecast_render::scene::Links;
    /// let l: Links = vec![[0, 1], [1, 2], [7, 3], [3, 4], [4, 5]].into();
    /// assert_eq!(l.iter_from(2).collect::<Vec<_>>(), vec![[7, 3], [3, 4], [4, 5]]);
    /// assert_eq!(l.iter_from(5).next(), None);
    /// ```
    pub fn iter_from(&self, k: usize) -> Iter<'_> {
        if k >= self.len {
            return Iter { links: self, seg: 0, k: self.len };
        }
        Iter { links: self, seg: self.seg_of(k), k }
    }

    /// The stretch holding link `k < len()`. First guess: stretches of equal length
    /// (streamlines of equal length: O(1)); else bisection.
    #[inline]
    fn seg_of(&self, k: usize) -> usize {
        let g = ((k as u128 * self.segs.len() as u128) / self.len as u128) as usize;
        let holds =
            |i: usize| self.segs[i].start as usize <= k && self.segs.get(i + 1).map_or(true, |s| s.start as usize > k);
        if holds(g) {
            g
        } else {
            self.segs.partition_point(|s| s.start as usize <= k) - 1
        }
    }

    /// True when `link` is one of the links.
    pub fn contains(&self, link: &[u32; 2]) -> bool {
        self.iter().any(|l| l == *link)
    }

    /// The links as a vector of pairs.
    pub fn to_vec(&self) -> Vec<[u32; 2]> {
        self.iter().collect()
    }

    /// Append link `[a, b]` as link number `len()`. A chain link (`b = a + 1`) that follows a
    /// chain link ending at `a` joins (or starts) a run.
    ///
    /// Panics at the 2³²-th link (a link index is a `u32`).
    pub fn push(&mut self, [a, b]: [u32; 2]) {
        let k = u32::try_from(self.len).ok().filter(|&k| k < u32::MAX).expect("at most 2³² − 1 links");
        self.len += 1;
        let chain = a.checked_add(1) == Some(b);
        let explicit = Seg { start: k, at: self.pairs.len() as u32, run: false };
        match self.segs.last_mut() {
            Some(s) if chain && s.run && s.at + (k - s.start) == a => {} // the run grows by one
            Some(s) if chain && !s.run && a > 0 && self.pairs.last() == Some(&[a - 1, a]) => {
                // The previous link (explicit until now) and this one start a run.
                self.pairs.pop();
                let run = Seg { start: k - 1, at: a - 1, run: true };
                match s.start == k - 1 {
                    true => *s = run,
                    false => self.segs.push(run),
                }
            }
            Some(s) if !s.run => self.pairs.push([a, b]),
            _ => {
                // A single chain link is stored explicitly; the next one turns the two into a run.
                self.segs.push(explicit);
                self.pairs.push([a, b]);
            }
        }
    }

    /// Bytes held (capacity, not length).
    pub fn memory_bytes(&self) -> usize {
        self.segs.capacity() * std::mem::size_of::<Seg>() + self.pairs.capacity() * std::mem::size_of::<[u32; 2]>()
    }

    /// Number of stored stretches (runs and groups of explicit pairs).
    pub fn stretches(&self) -> usize {
        self.segs.len()
    }

    /// Give back spare capacity.
    pub fn shrink_to_fit(&mut self) {
        self.segs.shrink_to_fit();
        self.pairs.shrink_to_fit();
    }
}

/// The links of a [`Links`] in order ([`Links::iter`]).
#[derive(Clone, Debug)]
pub struct Iter<'a> {
    links: &'a Links,
    seg: usize,
    k: usize,
}

impl Iterator for Iter<'_> {
    type Item = [u32; 2];

    #[inline]
    fn next(&mut self) -> Option<[u32; 2]> {
        let l = self.links;
        if self.k >= l.len {
            return None;
        }
        while l.segs.get(self.seg + 1).is_some_and(|s| s.start as usize <= self.k) {
            self.seg += 1;
        }
        let s = l.segs[self.seg];
        let out = Links::of(s, &l.pairs, (self.k - s.start as usize) as u32);
        self.k += 1;
        Some(out)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.links.len - self.k;
        (n, Some(n))
    }
}

impl ExactSizeIterator for Iter<'_> {}

impl<'a> IntoIterator for &'a Links {
    type Item = [u32; 2];
    type IntoIter = Iter<'a>;
    fn into_iter(self) -> Iter<'a> {
        self.iter()
    }
}

impl Extend<[u32; 2]> for Links {
    fn extend<I: IntoIterator<Item = [u32; 2]>>(&mut self, iter: I) {
        iter.into_iter().for_each(|l| self.push(l));
    }
}

impl FromIterator<[u32; 2]> for Links {
    fn from_iter<I: IntoIterator<Item = [u32; 2]>>(iter: I) -> Self {
        let mut l = Self::default();
        l.extend(iter);
        l
    }
}

impl From<Vec<[u32; 2]>> for Links {
    fn from(v: Vec<[u32; 2]>) -> Self {
        v.into_iter().collect()
    }
}

impl PartialEq for Links {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.iter().eq(other.iter())
    }
}

impl Eq for Links {}

impl PartialEq<Vec<[u32; 2]>> for Links {
    fn eq(&self, other: &Vec<[u32; 2]>) -> bool {
        self.len == other.len() && self.iter().eq(other.iter().copied())
    }
}

impl fmt::Debug for Links {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}
