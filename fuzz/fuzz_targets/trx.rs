#![no_main]
use libfuzzer_sys::fuzz_target;

mod check {
    include!("../checks/trx.rs");
}

fuzz_target!(|data: &[u8]| check::check(data));
