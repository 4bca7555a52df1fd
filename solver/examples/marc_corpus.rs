//! Reads every deck of the Mentat corpus (`COIL_MARC_DECKS`, default
//! /work/shared/marc-decks; skipped cleanly when absent) and prints, per deck, whether
//! it reads through or the first error. The decks are never copied into the repository.
//!
//! `cargo run -p coil-solver --example marc_corpus`

fn main() {
    let dir = std::env::var("COIL_MARC_DECKS").unwrap_or_else(|_| "/work/shared/marc-decks".into());
    let Ok(entries) = std::fs::read_dir(&dir) else {
        println!("no corpus at {dir}: skipped");
        return;
    };
    let mut paths: Vec<_> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "dat"))
        .collect();
    paths.sort();
    let mut through = 0;
    for p in &paths {
        match coil_solver::deck::read_file_noting(p) {
            Ok((_, notes)) => {
                through += 1;
                println!("READ  {} ({} cards not needed)", p.display(), notes.len());
            }
            Err(e) => println!("ERROR {e}"),
        }
    }
    println!("{through} of {} decks read through", paths.len());
}
