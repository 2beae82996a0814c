//! The file readers and writers, one binary (each file under `tests/` would be a crate of its
//! own to compile and link): round trips, malformed input refused with an error that names the
//! place, streaming, agreement with the field's reference readers, and the committed fuzz
//! corpora replayed through the fuzz targets' checks.
//!
//! Sizes are fixed by each test; none uses proptest, so `PROPTEST_CASES` changes nothing here.

mod fuzz_corpus;
mod npy;
mod obj;
mod obj_stream;
mod reference_readers;
mod stream;
mod swc;
mod swc_wild;
mod tck;
mod trk;
mod trx;
