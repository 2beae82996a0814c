//! The `tubecast` command line.
fn main() {
    eprintln!("tubecast: the command line is being built (see issue 5)");
    std::process::exit(2);
}
