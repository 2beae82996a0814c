#![no_main]
mod check {
    include!("../checks/sphere.rs");
}
libfuzzer_sys::fuzz_target!(|data: &[u8]| check::check(data));
