//! Recomputes the stored whole-BRDF reference (`crates/glazec-lab/data/reference/full-*.bin`)
//! of the subjects whose label contains NAME, in every set, and keeps every other subject's
//! values as stored: after a change to the reference that only some materials see (a base's
//! Fresnel factor, say), in minutes instead of the 18 of `glazec accuracy
//! --regenerate-full-reference`. Each subject's random stream is seeded by its index in its set,
//! so the values are those a full regeneration gives.
//!
//! A subject added at the end of its set since the file was written is computed too, if named.
//!
//! `cargo run --release -p glazec-lab --example refresh_full_reference -- NAME [NAME …]`

use glazec_lab::accuracy::full::{FullReference, sets, stored_reference};

fn main() -> Result<(), String> {
    let names: Vec<String> = std::env::args().skip(1).collect();
    if names.is_empty() {
        return Err("name at least one subject (a part of its label)".into());
    }
    for set in sets()? {
        let path = stored_reference(set.name);
        // A set that has grown at its end: read what is stored for the subjects before the new
        // ones, which must then be among those recomputed.
        let stored = (1..=set.subjects.len()).rev().find_map(|n| FullReference::read(&path, &set.subjects[..n]).ok());
        let mut reference = stored.ok_or_else(|| format!("{}: no stored subjects match the set", path.display()))?;
        reference.values.resize(set.subjects.len(), Vec::new());
        let which = |s: &glazec_lab::accuracy::full::Subject| names.iter().any(|n| s.label.contains(n.as_str()));
        let chosen: Vec<&str> = set.subjects.iter().filter(|s| which(s)).map(|s| s.label.as_str()).collect();
        if chosen.is_empty() {
            continue;
        }
        println!("{}: recomputing {}", set.name, chosen.join(", "));
        reference.recompute(&set.subjects, &which);
        if let Some(missing) = set.subjects.iter().zip(&reference.values).find(|(_, v)| v.is_empty()) {
            return Err(format!("{}: new in its set and not named, so not computed", missing.0.label));
        }
        reference.write(&path).map_err(|e| e.to_string())?;
    }
    Ok(())
}
