//! The worst probes of the whole-BRDF bands (`glazec_lab::accuracy::full`) for the default
//! method: per subject whose label contains NAME (every subject without one), its band figures
//! and its COUNT worst probes, every channel of glazec's CPU value against the stored reference.
//!
//! `cargo run --release -p glazec-lab --example worst_probes -- [NAME] [COUNT] [BAND]`, BAND one
//! of `Body`, `Grazing`, `Mirror` to list only that band's probes.

use glazec::model::Method;
use glazec_lab::accuracy::full::{
    FullReference, cpu_values, excess_error, measure, meets_targets, sets, stored_reference,
};

fn main() -> Result<(), String> {
    let filter = std::env::args().nth(1).unwrap_or_default();
    let count: usize = std::env::args().nth(2).and_then(|s| s.parse().ok()).unwrap_or(6);
    let band = std::env::args().nth(3);
    for set in sets()? {
        let reference = FullReference::read(&stored_reference(set.name), &set.subjects).map_err(|e| e.to_string())?;
        for (subject, reference) in set.subjects.iter().zip(&reference.values) {
            if !subject.label.contains(&filter) {
                continue;
            }
            let probes = subject.probes();
            let f = cpu_values(subject, Method::INTERFACED);
            let m = measure(&probes, &f, reference);
            println!(
                "{} / {}: meets the targets {}, body p90 {:.1}%, grazing max {:.1}%",
                set.name,
                subject.label,
                meets_targets(subject, &m),
                m.body_p90 * 100.0,
                m.grazing_max * 100.0
            );
            let mut worst: Vec<(f64, usize)> = (0..probes.len())
                .filter(|&i| band.as_ref().is_none_or(|b| format!("{:?}", probes[i].band).starts_with(b.as_str())))
                .map(|i| (excess_error(f[i], &reference[i]), i))
                .collect();
            worst.sort_by(|a, b| b.0.total_cmp(&a.0));
            for &(error, i) in worst.iter().take(count) {
                let (p, r) = (probes[i], &reference[i]);
                let theta = |w: glam::DVec3| w.z.acos().to_degrees();
                let phi = (p.wo.y.atan2(p.wo.x) - p.wi.y.atan2(p.wi.x)).to_degrees().rem_euclid(360.0);
                println!(
                    "  {:?} θi {:.0} θo {:.0} φ {:.0}: glazec {:.3e} {:.3e} {:.3e}, reference {:.3e} {:.3e} {:.3e} \
                     ± {:.1e} {:.1e} {:.1e}: {:.1}% beyond noise",
                    p.band,
                    theta(p.wi),
                    theta(p.wo),
                    phi,
                    f[i].x,
                    f[i].y,
                    f[i].z,
                    r.mean.x,
                    r.mean.y,
                    r.mean.z,
                    r.std_err.x,
                    r.std_err.y,
                    r.std_err.z,
                    error * 100.0
                );
            }
        }
    }
    Ok(())
}
