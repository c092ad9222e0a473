//! The stated albedo against the reference: the directional albedo a material's method states —
//! what image-based lighting weighs (the sum of `glazec::eval::environment_lobes`' weights, the
//! split sum's) and what a coat above takes for the layer under it — against the reference's
//! directional albedo (analog walks, `reference::Stack::albedo`), for every material of the
//! whole-BRDF sets ([`super::full::sets`]) at [`ALBEDO_THETAS`].
//!
//! The bands of [`super::full`] and the albedo metric of [`super::measure`] compare f (the latter
//! integrated by quadrature), which the stated albedo does not enter: a stack whose f is right can
//! state an albedo that is not, and its image-based lighting is then off by as much.

use std::path::{Path, PathBuf};

use glam::DVec3;
use glazec::math::sampling::direction_deg;
use glazec::model::Method;

use super::ALBEDO_THETAS;
use super::full::{FullReference, Set, Subject, excess_error};
use crate::reference::{self, Estimate, InterfaceMode, Stack};

/// Analog walks per directional albedo of the stored reference.
pub const ALBEDO_WALKS: u32 = 1 << 16;

/// Where the stored reference albedos of a set live in the lab's source tree.
pub fn stored_albedo_reference(set: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/reference").join(format!("albedo-{set}.bin"))
}

/// The reference's directional albedo of every subject at [`ALBEDO_THETAS`] (φ = 0), `walks`
/// each; a subject's random stream is seeded by its index, as for the bands.
pub fn compute(subjects: &[Subject], walks: u32, progress: &(dyn Fn(usize) + Sync)) -> FullReference {
    let values = crate::parallel_map(
        subjects.len(),
        |i| {
            let subject = &subjects[i];
            let stack = Stack::from_material(&subject.with_method(Method::INTERFACED), &subject.values);
            let opts = reference::Options {
                mode: InterfaceMode::Multiple,
                samples: walks,
                seed: i as u64,
                ..Default::default()
            };
            ALBEDO_THETAS.iter().map(|&t| stack.albedo(direction_deg(t, 0.0), &opts)).collect()
        },
        progress,
    );
    FullReference { samples: walks, values }
}

/// Reads a set's stored reference albedos.
///
/// # Errors
/// I/O errors, or a file that does not match the set.
pub fn read(path: &Path, subjects: &[Subject]) -> Result<FullReference, super::DataError> {
    FullReference::read_counted(path, subjects, &|_| ALBEDO_THETAS.len())
}

/// The default method's stated albedo of `subject` at [`ALBEDO_THETAS`] (φ = 0).
pub fn stated(subject: &Subject) -> Vec<DVec3> {
    let material = subject.with_method(Method::INTERFACED);
    ALBEDO_THETAS
        .iter()
        .map(|&t| {
            let v = direction_deg(t, 0.0).as_vec3();
            let lobes = glazec::eval::environment_lobes(&material, &subject.values, glam::Vec3::Z, v);
            lobes.iter().map(|lobe| lobe.weight).sum::<glam::Vec3>().as_dvec3()
        })
        .collect()
}

/// The signed relative error beyond noise of the channel that is furthest off (0 within 3
/// standard errors), per angle of [`ALBEDO_THETAS`].
pub fn errors(subject: &Subject, reference: &[Estimate]) -> Vec<f64> {
    stated(subject)
        .iter()
        .zip(reference)
        .map(|(&e, r)| {
            let size = excess_error(e, r);
            let channel = (0..3).max_by(|&a, &b| (e[a] - r.mean[a]).abs().total_cmp(&(e[b] - r.mean[b]).abs()));
            let sign = channel.map_or(1.0, |c| (e[c] - r.mean[c]).signum());
            sign * size
        })
        .collect()
}

/// The table of every set: per material (the worst of a group), the signed error at each angle
/// of the member that is furthest off anywhere.
///
/// # Errors
/// A set's stored albedos that cannot be read.
pub fn report(sets: &[Set]) -> Result<String, String> {
    let header: Vec<String> = ALBEDO_THETAS.iter().map(|t| format!("{t:.0}°")).collect();
    let mut md = format!(
        "**The stated albedo** (what image-based lighting weighs and a coat above takes: the sum of the \
         environment lobes' weights) against the reference's directional albedo ({ALBEDO_WALKS} walks per \
         angle), relative error beyond 3 standard errors, signed, of the channel furthest off; per group \
         its member furthest off:\n\n| material | {} |\n|---|{}\n",
        header.join(" | "),
        "---|".repeat(header.len())
    );
    for Set { name, title, subjects } in sets {
        let path = stored_albedo_reference(name);
        let reference = read(&path, subjects).map_err(|e| {
            format!("cannot read the reference {} (`glazec accuracy --regenerate-full-reference`): {e}", path.display())
        })?;
        md.push_str(&format!("| *{title}* |{}\n", " |".repeat(header.len())));
        let mut groups: Vec<(&str, Vec<f64>)> = Vec::new();
        for (subject, values) in subjects.iter().zip(&reference.values) {
            let e = errors(subject, values);
            let size = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            match groups.iter_mut().find(|(g, _)| *g == subject.group) {
                Some((_, worst)) if size(&e) > size(worst) => *worst = e,
                Some(_) => {}
                None => groups.push((&subject.group, e)),
            }
        }
        for (group, e) in groups {
            // (Within noise, or under 0.05%: no sign.)
            let cell = |x: f64| if x.abs() < 5e-4 { "0.0%".to_string() } else { format!("{:+.1}%", 100.0 * x) };
            let cells: Vec<String> = e.iter().map(|&x| cell(x)).collect();
            md.push_str(&format!("| {group} | {} |\n", cells.join(" | ")));
        }
    }
    Ok(md)
}
