//! The layer stack: coats, their lobes, and the opaque base a stack ends in.

use super::checker::Checker;
use super::fields::{
    COAT_FIELDS, CONDUCTOR_FIELDS, LAMBERT_FIELDS, LAYER_NAMES, PLASTIC_FIELDS, ROUGH_DIFFUSE_FIELDS,
    ROUGH_LOBE_FIELDS, one_of,
};
use super::rules::Rule;
use crate::diag::{Code, Diagnostic, Span, Spanned};
use crate::model::*;
use crate::parse::{Arg, Value};

impl Checker {
    pub(super) fn layers(&mut self, v: &Spanned<Value>) -> Option<(Vec<Coat>, Base)> {
        let Value::List(items) = &v.node else {
            self.wrong_type(
                v,
                "a list of layers",
                Some("write the stack top to bottom: `layers: [Coat(…), Lambert(…)]`"),
            );
            return None;
        };
        let Some((last, coats)) = items.split_last() else {
            self.error(
                Diagnostic::error(Code::EmptyStack, "the layer stack is empty", v.span, "no layers")
                    .with_help("a material needs at least an opaque base, e.g. `layers: [Lambert(albedo: 0.5)]`"),
            );
            return None;
        };
        self.layer_spans = items.iter().map(|i| i.span).collect();
        let mut ok = true;
        let mut checked_coats = Vec::new();
        for item in coats {
            let layer = self.layer(item);
            if let Some((map, span)) = self.layer_normal.take() {
                self.normals.push((checked_coats.len(), map, span));
            }
            match layer {
                Some(Layer::Coat(c)) => checked_coats.push(c),
                Some(Layer::Base(_)) => {
                    ok = false;
                    self.error(
                        Diagnostic::error(
                            Code::BaseNotLast,
                            "an opaque base must be the last layer",
                            item.span,
                            "this base hides every layer below it",
                        )
                        .with_help("list the stack top to bottom: coats first, then exactly one base"),
                    );
                }
                None => ok = false,
            }
        }
        let base_layer = self.layer(last);
        if let Some((map, span)) = self.layer_normal.take() {
            self.normals.push((checked_coats.len(), map, span));
        }
        let base = match base_layer {
            Some(Layer::Base(b)) => Some(b),
            Some(Layer::Coat(_)) => {
                self.error(
                    Diagnostic::error(
                        Code::BaseNotLast,
                        "the last layer must be an opaque base",
                        last.span,
                        "a coat cannot end the stack",
                    )
                    .with_help(format!("add a base below it: {}", one_of(&LAYER_NAMES[1..]))),
                );
                None
            }
            None => None,
        };
        if checked_coats.len() > MAX_COATS {
            self.error(
                Diagnostic::error(
                    Code::TooManyLayers,
                    format!("{} coat layers; at most {MAX_COATS} are supported", checked_coats.len()),
                    coats[MAX_COATS].span,
                    format!("coat {} is one too many", MAX_COATS + 1),
                )
                .with_help("merge layers with identical interfaces, or drop the ones that cannot be seen"),
            );
            ok = false;
        }
        if !ok {
            return None;
        }
        Some((checked_coats, base?))
    }

    pub(super) fn layer(&mut self, v: &Spanned<Value>) -> Option<Layer> {
        let (name, args) = self.constructor(v, "layer", LAYER_NAMES)?;
        let layer = match name.node.as_str() {
            "Coat" => Layer::Coat(self.coat(name, args, v.span)?),
            "Lambert" => {
                let f = self.fields(name, args, v.span, LAMBERT_FIELDS);
                self.normal_map(f.get(1))?;
                Layer::Base(Base::Lambert { albedo: self.color(f.get(0), Rule::Albedo)? })
            }
            "OrenNayar" | "Eon" => {
                let f = self.fields(name, args, v.span, ROUGH_DIFFUSE_FIELDS);
                self.normal_map(f.get(2))?;
                let sigma_rule = if name.node == "OrenNayar" { Rule::Sigma } else { Rule::Roughness };
                let albedo = self.color(f.get(0), Rule::Albedo);
                let roughness = self.scalar(f.get(1), sigma_rule);
                let (albedo, roughness) = (albedo?, roughness?);
                Layer::Base(if name.node == "OrenNayar" {
                    Base::OrenNayar { albedo, roughness }
                } else {
                    Base::Eon { albedo, roughness }
                })
            }
            "Conductor" => Layer::Base(self.conductor(name, args, v.span)?),
            "Measured" => Layer::Base(self.measured(name, args, v.span)?),
            _ => {
                let f = self.fields(name, args, v.span, PLASTIC_FIELDS);
                self.normal_map(f.get(3))?;
                let albedo = self.color(f.get(0), Rule::Albedo);
                let roughness = self.scalar(f.get(1), Rule::Roughness);
                let ior = self.scalar(f.get(2), Rule::Ior);
                Layer::Base(Base::Plastic { albedo: albedo?, roughness: roughness?, ior: ior? })
            }
        };
        Some(layer)
    }

    pub(super) fn coat(&mut self, name: &Spanned<String>, args: Option<&[Arg]>, whole: Span) -> Option<Coat> {
        let f = self.fields(name, args, whole, COAT_FIELDS);
        self.normal_map(f.get(4))?;
        let lobe = f.get(0).and_then(|v| self.lobe(v));
        let ior = self.scalar(f.get(1), Rule::Ior);
        let absorption = match f.get(2) {
            Some(v) => self.color(Some(v), Rule::Absorption),
            None => Some(Color::Lit([0.0; 3])),
        };
        let thickness = match f.get(3) {
            Some(v) => self.scalar(Some(v), Rule::Thickness),
            None => Some(Scalar::Lit(0.0)),
        };
        Some(Coat { lobe: lobe?, ior: ior?, absorption: absorption?, thickness: thickness? })
    }

    pub(super) fn lobe(&mut self, v: &Spanned<Value>) -> Option<Lobe> {
        let (name, args) = self.constructor(v, "lobe", Lobe::NAMES)?;
        if name.node == "Smooth" {
            self.no_arguments(name, args, v.span);
            return Some(Lobe::Smooth);
        }
        let f = self.fields(name, args, v.span, ROUGH_LOBE_FIELDS);
        let roughness = self.scalar(f.get(0), Rule::Roughness)?;
        Some(if name.node == "Ggx" { Lobe::Ggx { roughness } } else { Lobe::Gtr1 { roughness } })
    }

    pub(super) fn conductor(&mut self, name: &Spanned<String>, args: Option<&[Arg]>, whole: Span) -> Option<Base> {
        let f = self.fields(name, args, whole, CONDUCTOR_FIELDS);
        self.normal_map(f.get(4))?;
        let roughness = self.scalar(f.get(0), Rule::Roughness);
        let fresnel = match (f.get(1), f.get(2), f.get(3)) {
            (Some(f0), None, None) => self.color(Some(f0), Rule::Reflectance).map(ConductorFresnel::F0),
            (None, Some(eta), Some(k)) => {
                let eta = self.color(Some(eta), Rule::ConductorEta);
                let k = self.color(Some(k), Rule::Extinction);
                Some(ConductorFresnel::Complex { eta: eta?, k: k? })
            }
            (f0, eta, k) => {
                const HELP: &str = "write `f0: (1.0, 0.78, 0.34)` (Schlick's approximation) or \
                                    `eta: (0.17, 0.43, 1.44), k: (3.5, 2.46, 1.8)` (the exact conductor Fresnel)";
                let d = match (f0, eta, k) {
                    (Some(f0), ..) => {
                        let mut d = Diagnostic::error(
                            Code::ConductorFresnel,
                            "a conductor takes either `f0` or `eta` and `k`, not both",
                            f0.span,
                            "`f0` given here",
                        );
                        for (other, what) in [(eta, "`eta`"), (k, "`k`")] {
                            if let Some(other) = other {
                                d = d.with_secondary(other.span, format!("and {what} here"));
                            }
                        }
                        d
                    }
                    (None, Some(eta), None) => Diagnostic::error(
                        Code::ConductorFresnel,
                        "a conductor given `eta` also needs `k`",
                        eta.span,
                        "the real part of the complex IOR; the imaginary part `k` is missing",
                    ),
                    (None, None, Some(k)) => Diagnostic::error(
                        Code::ConductorFresnel,
                        "a conductor given `k` also needs `eta`",
                        k.span,
                        "the imaginary part of the complex IOR; the real part `eta` is missing",
                    ),
                    _ => Diagnostic::error(
                        Code::ConductorFresnel,
                        "a conductor needs its Fresnel reflectance: `f0`, or `eta` and `k`",
                        name.span,
                        "no `f0`, `eta` or `k`",
                    ),
                };
                self.error(d.with_help(HELP));
                None
            }
        };
        Some(Base::Conductor { roughness: roughness?, fresnel: fresnel? })
    }
}

pub(super) enum Layer {
    Coat(Coat),
    Base(Base),
}
