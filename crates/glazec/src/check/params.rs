//! Runtime parameters, textures and normal maps: where a number may be a `Param(…)` or a
//! `Texture(…)` instead of a literal.

use super::checker::Checker;
use super::fields::{NORMAL_MAP_FIELDS, PARAM_FIELDS, TEXTURE_FIELDS};
use super::rules::Rule;
use crate::diag::{Code, Diagnostic, Span, Spanned};
use crate::model::*;
use crate::parse::{Arg, Value};

impl Checker {
    /// Declares (or re-uses) a runtime parameter `Param("name", default)`.
    pub(super) fn param(
        &mut self,
        ctor: &Spanned<String>,
        args: Option<&[Arg]>,
        whole: Span,
        rule: Rule,
    ) -> Option<(ParamId, ParamValue)> {
        let f = self.fields(ctor, args, whole, PARAM_FIELDS);
        let name = f.get(0).and_then(|v| self.identifier(v, "parameter"));
        let default = f.get(1).and_then(|v| match &v.node {
            Value::Number(_) => self.number(v, rule).map(|x| ParamValue::Scalar(x as f32)),
            _ => self.rgb(v, rule).map(ParamValue::Rgb),
        });
        let (name, default) = (name?, default?);
        if let Some(&id) = self.param_ids.get(&name) {
            let first = self.params[id.0 as usize].default;
            let first_span = self.param_spans[id.0 as usize];
            if self.params[id.0 as usize].source != ParamSource::Uniform {
                self.error(
                    Diagnostic::error(
                        Code::ParamConflict,
                        format!("`{name}` is the name of a texture read"),
                        whole,
                        "declared as a uniform parameter here",
                    )
                    .with_secondary(first_span, "read from a texture here")
                    .with_help("rename the parameter"),
                );
                return None;
            }
            if first.type_name() != default.type_name() {
                self.error(
                    Diagnostic::error(
                        Code::ParamConflict,
                        format!("parameter `{name}` is declared with two types"),
                        whole,
                        format!("declared here as {}", default.type_name()),
                    )
                    .with_secondary(first_span, format!("first declared here as {}", first.type_name()))
                    .with_help("rename one of them, or give both defaults the same shape"),
                );
                return None;
            }
            if first != default {
                self.error(
                    Diagnostic::error(
                        Code::ParamConflict,
                        format!("parameter `{name}` is declared with two different defaults"),
                        whole,
                        "declared again here",
                    )
                    .with_secondary(first_span, "first declared here")
                    .with_help("a parameter has one default; repeat the same value or rename one"),
                );
                return None;
            }
            // The same parameter in another slot: it must suit both.
            let [lo, hi] = rule.bounds();
            let range = &mut self.params[id.0 as usize].range;
            *range = [range[0].max(lo), range[1].min(hi)];
            return Some((id, first));
        }
        let range = rule.bounds();
        let id = self.declare(Param { name, default, source: ParamSource::Uniform, range }, whole)?;
        Some((id, default))
    }

    /// Declares (or re-uses) a parameter read from a texture,
    /// `Texture("name", channel, uv_scale, range: (lo, hi))`. Its name is the texture's with the
    /// channel's suffix (`clay_maps_g`); `color_slot`: the slot takes a colour.
    pub(super) fn texture(
        &mut self,
        ctor: &Spanned<String>,
        args: Option<&[Arg]>,
        whole: Span,
        rule: Rule,
        color_slot: bool,
    ) -> Option<ParamId> {
        let f = self.fields(ctor, args, whole, TEXTURE_FIELDS);
        let texture = f.get(0).and_then(|v| self.identifier(v, "texture"));
        let channel = f.get(1).and_then(|v| self.channel(v, color_slot));
        let uv_scale = match f.get(2) {
            Some(v) => self.uv_scale(v),
            None => Some(1.0),
        };
        let range = match f.get(3) {
            Some(v) => self.texture_range(v, rule),
            None => self.default_texture_range(whole, rule),
        };
        let (texture, channel, uv_scale, range) = (texture?, channel?, uv_scale?, range?);
        let mid = 0.5 * (range[0] + range[1]);
        let default = if channel == Channel::Rgb { ParamValue::Rgb([mid; 3]) } else { ParamValue::Scalar(mid) };
        let name = format!("{texture}_{}", channel.suffix());
        let read = TextureRead { texture, channel, uv_scale, range };
        let source = ParamSource::Texture(read.clone());
        if let Some(&id) = self.param_ids.get(&name) {
            let first = &self.params[id.0 as usize];
            if first.source == source {
                return Some(id);
            }
            let first_span = self.param_spans[id.0 as usize];
            self.error(
                Diagnostic::error(
                    Code::ParamConflict,
                    format!("`{name}` is read twice in different ways"),
                    whole,
                    "read again here",
                )
                .with_secondary(first_span, "first read here")
                .with_help(
                    "a texture channel is one parameter: give every read of it the same uv_scale and range, or \
                     use another channel",
                ),
            );
            return None;
        }
        let textures = distinct_textures(&self.params, &[]);
        if !textures.contains(&read.texture.as_str()) && textures.len() == MAX_TEXTURES {
            self.error(
                Diagnostic::error(
                    Code::TooManyTextures,
                    format!("more than {MAX_TEXTURES} textures"),
                    whole,
                    format!("texture `{}` is one too many", read.texture),
                )
                .with_help("pack scalar maps into the channels of one texture (R, G, B, A)"),
            );
            return None;
        }
        self.declare(Param { name, default, source, range: rule.bounds() }, whole)
    }

    /// Adds a new parameter, unless there are [`MAX_PARAMS`] already (`E0219`).
    pub(super) fn declare(&mut self, param: Param, whole: Span) -> Option<ParamId> {
        if self.params.len() == MAX_PARAMS {
            self.error(
                Diagnostic::error(
                    Code::TooManyParams,
                    format!("more than {MAX_PARAMS} runtime parameters"),
                    whole,
                    format!("parameter {} is one too many", MAX_PARAMS + 1),
                )
                .with_help("fold the values that never change into literals"),
            );
            return None;
        }
        let id = ParamId(self.params.len() as u16);
        self.param_ids.insert(param.name.clone(), id);
        self.params.push(param);
        self.param_spans.push(whole);
        Some(id)
    }

    /// A layer's `normal: NormalMap("texture", uv_scale, detail: "texture", detail_scale)`;
    /// `None` if it is malformed (reported), else remembered for `layers`.
    pub(super) fn normal_map(&mut self, v: Option<&Spanned<Value>>) -> Option<()> {
        let Some(v) = v else { return Some(()) };
        let (name, args) = self.constructor(v, "normal map", &["NormalMap"])?;
        let f = self.fields(name, args, v.span, NORMAL_MAP_FIELDS);
        let texture = f.get(0).and_then(|t| self.identifier(t, "texture"));
        let uv_scale = f.get(1).map_or(Some(1.0), |x| self.uv_scale(x));
        let detail = f.get(2).map(|t| self.identifier(t, "texture"));
        let detail_scale = f.get(3).map_or(Some(1.0), |x| self.uv_scale(x));
        let detail = match detail {
            Some(t) => Some((t?, detail_scale?)),
            None => None,
        };
        self.layer_normal = Some((NormalMap { texture: texture?, uv_scale: uv_scale?, detail }, v.span));
        Some(())
    }

    /// At most [`MAX_TEXTURES`] textures, counting normal maps (E0220 at the first one too many).
    pub(super) fn texture_count(&mut self, material: &Material) -> Option<()> {
        let textures = material.textures();
        if textures.len() <= MAX_TEXTURES {
            return Some(());
        }
        let extra = textures[MAX_TEXTURES];
        let span = self.normals.iter().find(|(_, m, _)| m.textures().any(|t| t == extra)).map(|(_, _, s)| *s);
        let Some(span) = span else { return Some(()) }; // (texture reads are counted as they are read)
        self.error(
            Diagnostic::error(
                Code::TooManyTextures,
                format!("more than {MAX_TEXTURES} textures"),
                span,
                format!("texture `{extra}` is one too many"),
            )
            .with_help("pack scalar maps into the channels of one texture (R, G, B, A)"),
        );
        None
    }

    /// A channel `R`, `G`, `B`, `A` or (in a colour slot) `Rgb`.
    pub(super) fn channel(&mut self, v: &Spanned<Value>, color_slot: bool) -> Option<Channel> {
        let (name, args) = self.constructor(v, "texture channel", Channel::NAMES)?;
        self.no_arguments(name, args, v.span);
        let channel = Channel::ALL.into_iter().find(|c| Channel::NAMES[*c as usize] == name.node)?;
        if channel == Channel::Rgb && !color_slot {
            self.wrong_type(
                v,
                "one channel (R, G, B or A)",
                Some("this slot takes one number; read one channel of the texture"),
            );
            return None;
        }
        Some(channel)
    }

    /// `uv_scale`: a positive number of repeats.
    pub(super) fn uv_scale(&mut self, v: &Spanned<Value>) -> Option<f32> {
        let x = match v.node {
            Value::Number(x) => x,
            _ => {
                self.wrong_type(v, "a number", Some("uv_scale is how often the texture repeats across the surface"));
                return None;
            }
        };
        if !(x.is_finite() && x > 0.0 && x <= 1e6) {
            self.error(
                Diagnostic::error(
                    Code::TextureRange,
                    "uv_scale must be a positive number",
                    v.span,
                    "must lie in (0, 10⁶]",
                )
                .with_help("uv_scale is how often the texture repeats across uv ∈ [0, 1]; 1 maps it once"),
            );
            return None;
        }
        Some(x as f32)
    }

    /// `range: (lo, hi)`: the slot's values at texel values 0 and 1; both inside the slot's range.
    pub(super) fn texture_range(&mut self, v: &Spanned<Value>, rule: Rule) -> Option<[f32; 2]> {
        match &v.node {
            Value::Call { name: None, args: Some(items) }
                if items.len() == 2 && items.iter().all(|a| a.name.is_none()) =>
            {
                let lo = self.number(&items[0].value, rule);
                let hi = self.number(&items[1].value, rule);
                Some([lo? as f32, hi? as f32])
            }
            _ => {
                self.wrong_type(
                    v,
                    "a pair `(lo, hi)`",
                    Some("range gives the slot's values at texel values 0 and 1, e.g. `range: (0.1, 0.6)`"),
                );
                None
            }
        }
    }

    /// A texel lies in [0, 1]: that is the range when the slot's own range is [0, 1]; any other
    /// slot must say how texels map onto it.
    pub(super) fn default_texture_range(&mut self, whole: Span, rule: Rule) -> Option<[f32; 2]> {
        if rule.accepts(0.0) && rule.accepts(1.0) {
            return Some([0.0, 1.0]);
        }
        self.error(
            Diagnostic::error(
                Code::TextureRange,
                format!("a texture for the {} needs a `range`", rule.what()),
                whole,
                format!("texels lie in [0, 1]; the {} {}", rule.what(), rule.label()),
            )
            .with_help("map texel values onto the slot with `range: (lo, hi)`, e.g. `range: (1.3, 1.6)`"),
        );
        None
    }
}
