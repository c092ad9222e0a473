//! The report of a simplification: each change kept (with its error and saving) and each tried
//! and refused, in Markdown.

use std::fmt::Write as _;

use super::samples::PASS_BUDGET;
use crate::model::{Base, Lobe, Material, Scalar};
use crate::scene::Scene;

/// One accepted change.
#[derive(Clone, Debug)]
pub struct Step {
    pub change: String,
    /// max ΔL / allowed against the original material, on the pass's sample set.
    pub error: f32,
    pub cost_before: usize,
    pub cost_after: usize,
}

/// A change that was tried and not kept.
#[derive(Clone, Debug)]
pub struct Rejected {
    pub change: String,
    pub error: f32,
    pub cost: usize,
}

/// What `simplify` did, and why.
#[derive(Clone, Debug)]
pub struct Report {
    pub material: String,
    pub scene: String,
    pub scene_summary: String,
    pub samples: String,
    pub steps: Vec<Step>,
    pub rejected: Vec<Rejected>,
    pub full_cost: usize,
    pub simplified_cost: usize,
    /// max ΔL / allowed of the result, on the pass's sample set.
    pub final_error: f32,
}

impl Report {
    /// The report as Markdown; `explain` adds the changes that were tried and not kept.
    pub fn markdown(&self, explain: bool) -> String {
        let mut out = format!("# `{}` simplified for scene `{}`\n\n", self.material, self.scene);
        let _ = writeln!(out, "Scene: {}.\n", self.scene_summary);
        let _ = writeln!(out, "Error measure: {}.\n", self.samples);
        if self.steps.is_empty() {
            out.push_str("No change fits the tolerance: the material is compiled as written.\n\n");
        } else {
            out.push_str("| step | change | error (share of tolerance) | cost (expressions) |\n|---|---|---|---|\n");
            for (i, s) in self.steps.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "| {} | {} | {} | {} → {} ({}) |",
                    i + 1,
                    s.change,
                    share(s.error),
                    s.cost_before,
                    s.cost_after,
                    percent(s.cost_before, s.cost_after)
                );
            }
            out.push('\n');
        }
        let _ = writeln!(
            out,
            "Result: cost {} → {} expressions ({}); error {} of the tolerance against the full material.\n",
            self.full_cost,
            self.simplified_cost,
            percent(self.full_cost, self.simplified_cost),
            share(self.final_error)
        );
        if explain {
            if self.rejected.is_empty() {
                out.push_str("Nothing else was tried: no other change lowers the cost.\n");
            } else {
                out.push_str("Kept, because removing it shows (error above the pass's budget of ");
                let _ = writeln!(out, "{PASS_BUDGET} of the tolerance):\n");
                out.push_str("| change | error (share of tolerance) | cost it would have |\n|---|---|---|\n");
                for r in &self.rejected {
                    let _ = writeln!(out, "| {} | {} | {} |", r.change, share(r.error), r.cost);
                }
            }
        }
        out
    }
}

pub(super) fn coat_summary(material: &Material, i: usize) -> String {
    let coat = &material.coats[i];
    let lobe = match coat.lobe {
        Lobe::Smooth => "smooth".to_string(),
        Lobe::Ggx { roughness } => format!("GGX {}", scalar_text(material, roughness)),
        Lobe::Gtr1 { roughness } => format!("GTR1 {}", scalar_text(material, roughness)),
    };
    format!("{lobe}, IOR {}", scalar_text(material, coat.ior))
}

fn scalar_text(material: &Material, s: Scalar) -> String {
    match s {
        Scalar::Lit(x) => format!("{x}"),
        Scalar::Param(id) => format!("`{}`", material.params[id.0 as usize].name),
    }
}

pub(super) fn base_name(base: &Base) -> &'static str {
    match base {
        Base::Lambert { .. } => "Lambert",
        Base::OrenNayar { .. } => "Oren–Nayar",
        Base::Eon { .. } => "EON",
        Base::Conductor { .. } => "conductor",
        Base::Plastic { .. } => "plastic",
    }
}

fn percent(before: usize, after: usize) -> String {
    if before == 0 {
        return "—".into();
    }
    format!("{:+.0}%", 100.0 * (after as f64 - before as f64) / before as f64)
}

pub(super) fn scene_summary(scene: &Scene) -> String {
    let total = scene.lights.iter().fold([0.0_f32; 3], |acc, l| {
        let e = l.max_irradiance();
        [acc[0] + e[0], acc[1] + e[1], acc[2] + e[2]]
    });
    let env = scene.environment.map_or("no environment".to_string(), |l| format!("environment ≤ {}", rgb_text(l)));
    format!(
        "{} light(s), Σ irradiance ≤ {}; {env}; view ≤ {}°, light ≤ {}° from the normal; exposure {}; tolerance {}",
        scene.lights.len(),
        rgb_text(total),
        scene.view_max_angle,
        scene.light_max_angle,
        scene.exposure,
        scene.tolerance.describe()
    )
}

fn rgb_text(c: [f32; 3]) -> String {
    let short = |x: f32| format!("{}", (x * 1000.0).round() / 1000.0);
    format!("({}, {}, {})", short(c[0]), short(c[1]), short(c[2]))
}

/// A share of the tolerance: three decimals, or scientific notation when it is huge.
pub(super) fn share(x: f32) -> String {
    if x < 1000.0 { format!("{x:.3}") } else { format!("{x:.2e}") }
}

// ---------------------------------------------------------------------------------------------
// Parameters
