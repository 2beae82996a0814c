//! The kernels' shared maths, each written once (crate-private): quadric roots and slab
//! clipping ([`quadric`]), polynomial root finders and the derivative cascade ([`roots`]),
//! quadratic Bézier evaluation and extrema ([`bezier`]), certified root counts by
//! Descartes' rule in the Bernstein basis ([`descartes`]), orthonormal frames ([`frame`]) and a
//! golden-section minimiser ([`minimise`]).
//!
//! Items that `crate::kernel` re-exports under their historical public paths are `pub` here;
//! the module itself is private.

pub(crate) mod bezier;
pub(crate) mod descartes;
pub(crate) mod frame;
pub(crate) mod minimise;
pub(crate) mod quadric;
pub(crate) mod roots;
