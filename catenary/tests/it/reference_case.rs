//! The EN 50318:2002 reference case (`cases/catenary-en50318-2002`) against its ranges:
//! every statistic at 250 and 300 km/h inside its range (the README's table). Two runs of
//! about 50 000 steps: `#[ignore]`d, run with
//! `cargo test --release -p coil-catenary --test it reference_case -- --ignored --nocapture`.

use coil_catenary::case::read_case;
use coil_catenary::run::run_case;
use coil_postproc::en50318::report::{verdicts, Verdict};
use std::path::Path;

#[test]
#[ignore = "two 10-span runs at 0.125 ms steps (tens of seconds)"]
fn the_reference_case_meets_every_range() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/catenary-en50318-2002");
    let case = read_case(&root).unwrap();
    let outcome = run_case(&case).unwrap();
    let mut missed = Vec::new();
    for run in &outcome.runs {
        for row in verdicts(&run.statistics, &case.reference) {
            println!(
                "{:.0} km/h {}: {:.2} in {:?}: {:?}",
                run.statistics.speed_km_h, row.key, row.value, row.range, row.verdict
            );
            assert_ne!(row.verdict, Verdict::NoRange, "{}", row.key);
            if row.verdict == Verdict::Miss {
                missed.push(format!("{} at {}", row.key, run.statistics.speed_km_h));
            }
        }
    }
    assert!(missed.is_empty(), "missed: {missed:?}");
}
