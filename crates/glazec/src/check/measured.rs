//! `Measured(…)`: a diffuse base declared from reflectance measurements (the clay-optics paper);
//! `check` solves for σa and σs′ per channel ([`crate::optics`]) and uses the diffuse albedo they
//! imply.
//!
//! ```ron
//! // Over a black and over a white backing (Kubelka–Munk, closed form):
//! Measured(reflectance_black: (0.38, 0.27, 0.2), reflectance_white: (0.45, 0.34, 0.27), backing: 0.9, thickness: 1.0)
//! // One reflectance and a known reduced scattering coefficient (exponential slab model):
//! Measured(reflectance: (0.3, 0.2, 0.15), scattering: 12.0, thickness: 0.1, ior: 1.5)
//! ```
//!
//! Optional `roughness` makes the base EON (else Lambert). The derived coefficients are reported
//! in a note (`N0401`); a single reflectance is `E0401`, readings no layer produces `E0402`.

use super::checker::Checker;
use super::fields::{FieldSpec, opt, req};
use super::rules::Rule;
use crate::diag::{Code, Diagnostic, Severity, Span, Spanned};
use crate::model::{Base, Color, Scalar};
use crate::optics::{self, Observation, OpticsError, Slab, SlabModel};
use crate::parse::Arg;

const MEASURED_FIELDS: &[FieldSpec] = &[
    opt("reflectance_black", "(0.38, 0.27, 0.2)"),
    opt("reflectance_white", "(0.45, 0.34, 0.27)"),
    opt("backing", "0.9"),
    opt("reflectance", "(0.3, 0.2, 0.15)"),
    opt("scattering", "12.0"),
    req("thickness", "1.0"),
    opt("ior", "1.5"),
    opt("roughness", "0.5"),
];

/// Which measurements a `Measured` gives.
enum Form {
    BlackWhite { black: [f32; 3], white: [f32; 3], backing: [f32; 3] },
    KnownScattering { reflectance: [f32; 3], scattering: [f32; 3], backing: [f32; 3] },
}

impl Checker {
    pub(super) fn measured(&mut self, ctor: &Spanned<String>, args: Option<&[Arg]>, whole: Span) -> Option<Base> {
        let f = self.fields(ctor, args, whole, MEASURED_FIELDS);
        let mut rgb = |i: usize, rule: Rule| f.get(i).map(|v| self.rgb(v, rule));
        let black = rgb(0, Rule::Albedo);
        let white = rgb(1, Rule::Albedo);
        let backing = rgb(2, Rule::Albedo);
        let reflectance = rgb(3, Rule::Albedo);
        let scattering = rgb(4, Rule::Absorption);
        let thickness = f.get(5).and_then(|v| self.number(v, Rule::Thickness));
        let ior = f.get(6).map(|v| self.number(v, Rule::Ior));
        let roughness = f.get(7).map(|v| self.number(v, Rule::Roughness));
        let form = match (black, white, reflectance, scattering) {
            (Some(b), Some(w), None, None) => {
                let Some(backing) = backing else {
                    self.error(missing(whole, "backing", "the reflectance of the white backing, e.g. `backing: 0.9`"));
                    return None;
                };
                Form::BlackWhite { black: b?, white: w?, backing: backing? }
            }
            (None, None, Some(r), Some(s)) => {
                Form::KnownScattering { reflectance: r?, scattering: s?, backing: backing.unwrap_or(Some([0.0; 3]))? }
            }
            (None, None, Some(r), None) => {
                r?;
                self.error(single_reflectance(f.get(3).map_or(whole, |v| v.span)));
                return None;
            }
            (Some(_), None, _, _) | (None, Some(_), _, _) => {
                let (have, need) = if f.get(0).is_some() {
                    ("reflectance_black", "reflectance_white")
                } else {
                    ("reflectance_white", "reflectance_black")
                };
                self.error(missing(
                    whole,
                    need,
                    &format!("`{have}` needs `{need}` and `backing`: a reading over each backing"),
                ));
                return None;
            }
            _ => {
                self.error(
                    Diagnostic::error(
                        Code::ImpossibleMeasurement,
                        "`Measured` takes either readings over black and white backing, or one reflectance with `scattering`",
                        whole,
                        "mixes or lacks measurements",
                    )
                    .with_help("give `reflectance_black`, `reflectance_white` and `backing`, or `reflectance` and `scattering`"),
                );
                return None;
            }
        };
        let thickness = thickness?;
        let eta = match ior {
            Some(v) => v?,
            None => 1.5,
        };
        let roughness = match roughness {
            Some(v) => Some(v? as f32),
            None => None,
        };
        let (albedo, note) = self.solve_measured(&form, thickness, eta, whole)?;
        self.notes.push(note);
        let albedo = Color::Lit(albedo);
        Some(match roughness {
            Some(r) => Base::Eon { albedo, roughness: Scalar::Lit(r) },
            None => Base::Lambert { albedo },
        })
    }

    /// Solves each channel; returns the albedo and the note, or reports why not.
    fn solve_measured(&mut self, form: &Form, thickness: f64, eta: f64, whole: Span) -> Option<([f32; 3], Diagnostic)> {
        let mut solutions = Vec::with_capacity(3);
        for c in 0..3 {
            let observation = match form {
                Form::BlackWhite { black, white, backing } => Observation::BlackWhite {
                    r_black: f64::from(black[c]),
                    r_white: f64::from(white[c]),
                    backing: f64::from(backing[c]),
                    thickness,
                },
                Form::KnownScattering { reflectance, scattering, backing } => Observation::KnownScattering {
                    model: SlabModel::Exponential,
                    slab: Slab {
                        f_top: optics::diffuse_fresnel_external(eta),
                        f_bottom: f64::from(backing[c]),
                        p_g: 0.5,
                        eta,
                    },
                    d: thickness,
                    r: f64::from(reflectance[c]),
                    sigma_s: f64::from(scattering[c]),
                },
            };
            match optics::solve(&observation) {
                Ok(s) => solutions.push(s),
                Err(e) => {
                    let channel = ["red", "green", "blue"][c];
                    let d = match e {
                        OpticsError::SingleReflectance => single_reflectance(whole),
                        e => Diagnostic::error(
                            Code::ImpossibleMeasurement,
                            format!("the {channel} channel's measurements have no solution"),
                            whole,
                            "these readings",
                        )
                        .with_help(e.to_string()),
                    };
                    self.error(d);
                    return None;
                }
            }
        }
        let triple = |f: &dyn Fn(&optics::Solution) -> f64| {
            format!("({})", solutions.iter().map(|s| format!("{:.4}", f(s))).collect::<Vec<_>>().join(", "))
        };
        let how = match form {
            Form::BlackWhite { .. } => "Kubelka–Munk over black and white backing; albedo = R∞",
            Form::KnownScattering { .. } => "exponential slab with the given σs′; albedo from the diffusion dipole",
        };
        let mut note = Diagnostic::error(
            Code::DerivedOptics,
            format!(
                "measured: σa = {}, σs′ = {} per unit length; diffuse albedo {}",
                triple(&|s| s.sigma_a),
                triple(&|s| s.sigma_s),
                triple(&|s| s.albedo)
            ),
            whole,
            how,
        );
        note.severity = Severity::Note;
        for s in &solutions {
            for w in &s.warnings {
                note = note.with_help(w.clone());
            }
        }
        let albedo = [0, 1, 2].map(|c| solutions[c].albedo as f32);
        Some((albedo, note))
    }
}

fn single_reflectance(span: Span) -> Diagnostic {
    Diagnostic::error(Code::SingleReflectance, "one reflectance cannot fix both σa and σs′", span, "a single reading")
        .with_help(
            "add readings over a black and a white backing (`reflectance_black`, `reflectance_white`, `backing`), \
             or the reduced scattering coefficient (`scattering: …`)",
        )
}

fn missing(whole: Span, field: &str, help: &str) -> Diagnostic {
    Diagnostic::error(
        Code::MissingField,
        format!("missing field `{field}` in `Measured`"),
        whole,
        format!("needs `{field}`"),
    )
    .with_help(help.to_string())
}
