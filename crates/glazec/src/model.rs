//! The material model: what a checked material *is*, as plain typed data.
//!
//! `check` produces a [`Material`]; `lower` (the shader) and `eval` (the CPU) consume it through
//! the same BRDF code in [`crate::math`]. There are no spans in here: spans live in the side
//! table [`SourceMap`] so that the model can be built by programs (tests, proptest, the
//! `build.rs` API) as easily as by the parser.
//!
//! **Invariants** (established by `check`, assumed downstream): the material name is a valid
//! identifier; every literal is finite and inside its physical range (roughness and albedo in
//! `[0, 1]`, IOR > 0, absorption and thickness ≥ 0); every [`ParamId`] indexes
//! [`Material::params`]; parameter names are unique; a parameter's default obeys the same range
//! as every slot it is used in.
//!
//! Conventions: the stack is listed **top to bottom**; each coat's `ior` is relative to the
//! medium directly above it; `roughness` is perceptual (α = roughness², as in Burley 2012),
//! except for Oren–Nayar, whose roughness is the facet-slope deviation σ in radians.

/// A complete layered material: coats (top to bottom) over one opaque base.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// A lowercase identifier; it names the output files and the shader functions.
    pub name: String,
    pub method: Method,
    /// Coat layers, top to bottom. May be empty (a bare base).
    pub coats: Vec<Coat>,
    pub base: Base,
    /// Runtime parameters in order of first use; they become one uniform struct.
    pub params: Vec<Param>,
    /// Normal maps, by layer (index into the coats; `coats.len()` is the base), in layer order.
    /// A layer without one uses the surface normal.
    pub normals: Vec<(usize, NormalMap)>,
}

/// The textures that `params` read and `normals` use, each once: the reads in order of first
/// use, then the maps in order (their bindings follow this order).
pub fn distinct_textures<'a>(params: &'a [Param], normals: &'a [(usize, NormalMap)]) -> Vec<&'a str> {
    let reads = params.iter().filter_map(|p| match &p.source {
        ParamSource::Texture(read) => Some(read.texture.as_str()),
        ParamSource::Uniform => None,
    });
    let maps = normals.iter().flat_map(|(_, m)| m.textures());
    let mut names: Vec<&str> = Vec::new();
    for name in reads.chain(maps) {
        if !names.contains(&name) {
            names.push(name);
        }
    }
    names
}

/// A tangent-space normal map on one layer, optionally blended with a detail map by reoriented
/// normal mapping (Barré-Brisebois & Hill 2012, "Blending in Detail").
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMap {
    /// The texture (RGB = tangent-space normal · ½ + ½, as normal maps are stored).
    pub texture: String,
    pub uv_scale: f32,
    /// A second map, blended onto the first: (texture, uv_scale).
    pub detail: Option<(String, f32)>,
}

impl NormalMap {
    /// The map's texture, then its detail map's.
    pub fn textures(&self) -> impl Iterator<Item = &str> {
        std::iter::once(self.texture.as_str()).chain(self.detail.as_ref().map(|(t, _)| t.as_str()))
    }
}

/// How a stack of layers is combined into one BRDF.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Disney clear-coat (Burley 2012; Bowsher 2022, §3.0.2): each coat adds a specular lobe on
    /// top of the base, with no attenuation. The cheapest; creates energy.
    Additive,
    /// The recurrence of Weidlich & Wilkie 2007 as the seed writes it (Bowsher 2022, §3.0.3,
    /// eq. 12–19). Kept faithful so it can be measured.
    WeidlichWilkie,
    /// glazec's default: reciprocal, energy-conserving layering that is exact for a smooth
    /// dielectric coat over a Lambertian base with absorption (η² radiance compression, internal
    /// reflection including TIR, absorption along refracted paths). Cheaper approximations
    /// can be asked for (`Interfaced(fresnel: Schlick, multiple_scattering: false)`); `glazec
    /// bench` measures what each costs and loses.
    Interfaced(Approximations),
}

impl Default for Method {
    fn default() -> Self {
        Method::INTERFACED
    }
}

/// Approximations the interfaced method may take to save time, all off by default.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Approximations {
    /// Schlick's approximation (Schlick 1994) for the coats' dielectric Fresnel reflectance
    /// instead of the exact formula (`fresnel: Schlick`; default `Exact`).
    pub schlick_fresnel: bool,
    /// Leave out the light a rough coat reflects after several microfacet bounces (the scaling of
    /// its lobe that compensates for them): it is lost, as in a single-scattering microfacet model
    /// (`multiple_scattering: false`; default `true`).
    pub single_scattering: bool,
}

impl Approximations {
    /// The approximations taken, each as (its argument in a material file, its name in reports).
    pub fn taken(self) -> impl Iterator<Item = (&'static str, &'static str)> {
        [
            (self.schlick_fresnel, ("fresnel: Schlick", "Schlick Fresnel")),
            (self.single_scattering, ("multiple_scattering: false", "no multiple scattering")),
        ]
        .into_iter()
        .filter_map(|(on, names)| on.then_some(names))
    }
}

impl Method {
    pub const NAMES: &'static [&'static str] = &["Additive", "WeidlichWilkie", "Interfaced"];
    /// The default method with no approximations.
    pub const INTERFACED: Method =
        Method::Interfaced(Approximations { schlick_fresnel: false, single_scattering: false });
    /// The interfaced method with Schlick's Fresnel.
    pub const INTERFACED_SCHLICK: Method =
        Method::Interfaced(Approximations { schlick_fresnel: true, single_scattering: false });
    /// The interfaced method without multiple-scattering compensation.
    pub const INTERFACED_SINGLE_SCATTERING: Method =
        Method::Interfaced(Approximations { schlick_fresnel: false, single_scattering: true });
    /// Every method and variant that `glazec bench` measures.
    pub const MEASURED: [Method; 5] = [
        Method::INTERFACED,
        Method::INTERFACED_SCHLICK,
        Method::INTERFACED_SINGLE_SCATTERING,
        Method::WeidlichWilkie,
        Method::Additive,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Method::Additive => "Additive",
            Method::WeidlichWilkie => "WeidlichWilkie",
            Method::Interfaced(_) => "Interfaced",
        }
    }

    /// The method as a material file writes it, approximations included.
    pub fn source(self) -> String {
        match self {
            Method::Interfaced(a) if a != Approximations::default() => {
                let args: Vec<&str> = a.taken().map(|(source, _)| source).collect();
                format!("Interfaced({})", args.join(", "))
            }
            _ => self.name().to_string(),
        }
    }
}

/// A dielectric coat: an interface (its lobe and IOR) over an absorbing slab.
#[derive(Clone, Debug, PartialEq)]
pub struct Coat {
    pub lobe: Lobe,
    /// Index of refraction relative to the medium above.
    pub ior: Scalar,
    /// Absorption coefficient σa per unit length, per RGB channel.
    pub absorption: Color,
    /// Slab thickness d (the seed's "density"); the optical depth is τ = σa·d.
    pub thickness: Scalar,
}

/// The microfacet lobe of a coat's top interface.
#[derive(Clone, Debug, PartialEq)]
pub enum Lobe {
    /// A perfectly flat interface: a mirror reflection (a delta lobe, invisible to point lights)
    /// and a sharp refraction.
    Smooth,
    /// GGX / Trowbridge–Reitz microfacets (Walter et al. 2007), α = roughness².
    Ggx { roughness: Scalar },
    /// The Disney clear-coat lobe: GTR1 distribution (Burley 2012), α = roughness².
    Gtr1 { roughness: Scalar },
}

impl Lobe {
    pub const NAMES: &'static [&'static str] = &["Smooth", "Ggx", "Gtr1"];
}

/// The opaque layer at the bottom of the stack.
#[derive(Clone, Debug, PartialEq)]
pub enum Base {
    /// Lambertian diffuse, f = ρ/π.
    Lambert { albedo: Color },
    /// The qualitative Oren–Nayar model (Oren & Nayar 1994; Bowsher 2022, eq. 17); `roughness`
    /// is σ in radians.
    OrenNayar { albedo: Color, roughness: Scalar },
    /// Energy-preserving Oren–Nayar (Portsmouth, Kutz & Hill 2025), roughness r ∈ [0, 1].
    Eon { albedo: Color, roughness: Scalar },
    /// A rough conductor: GGX microfacets with a conductor Fresnel term.
    Conductor { roughness: Scalar, fresnel: ConductorFresnel },
    /// A rough dielectric over a diffuse body (plastic). Lowered as a GGX coat of zero
    /// thickness over a Lambertian base, so it obeys the material's method like any coat.
    Plastic { albedo: Color, roughness: Scalar, ior: Scalar },
}

impl Base {
    pub const NAMES: &'static [&'static str] = &["Lambert", "OrenNayar", "Eon", "Conductor", "Plastic"];
}

/// How a conductor's Fresnel reflectance is given.
#[derive(Clone, Debug, PartialEq)]
pub enum ConductorFresnel {
    /// Normal-incidence reflectance, used with Schlick's approximation.
    F0(Color),
    /// Complex IOR η + iκ per channel (relative to vacuum), used with the exact conductor Fresnel.
    Complex { eta: Color, k: Color },
}

/// A scalar slot: a literal folded into the shader, or a runtime parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scalar {
    Lit(f32),
    Param(ParamId),
}

/// An RGB slot: a literal, or a runtime parameter (a scalar parameter is broadcast to grey).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Color {
    Lit([f32; 3]),
    Param(ParamId),
}

/// Index into [`Material::params`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ParamId(pub u16);

/// A named runtime parameter: one member of the material's uniform struct, or a value read from
/// a texture at each shading point.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub name: String,
    /// Its value when nothing else is given. A texture read's default is the value of a
    /// mid-grey texel (0.5 in every channel): the middle of its range.
    pub default: ParamValue,
    pub source: ParamSource,
    /// The values the slots it fills accept (language.md's table of fields: [0, 1] for a
    /// roughness, [0.1, 10] for a coat's IOR, …; the intersection for a parameter used in
    /// several slots). A host's value outside it is a value the checker would have refused as
    /// a literal; hosts clamp user input to it (the playground's sliders span it).
    pub range: [f32; 2],
}

/// Where a runtime parameter's value comes from.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum ParamSource {
    /// A member of the uniform struct `<Material>Params`.
    #[default]
    Uniform,
    /// A texture channel, sampled at the shading point's uv (`Texture(name, channel, uv_scale)`).
    Texture(TextureRead),
}

/// One channel of a texture, mapped onto a parameter's range.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureRead {
    /// The texture's name: it names its binding in generated code.
    pub texture: String,
    pub channel: Channel,
    /// The texture repeats this many times across uv ∈ [0, 1].
    pub uv_scale: f32,
    /// The parameter's values at texel values 0 and 1 (linear in between).
    pub range: [f32; 2],
}

impl TextureRead {
    /// The parameter's value at texel value `t`.
    pub fn value(&self, t: f32) -> f32 {
        self.range[0] + (self.range[1] - self.range[0]) * t
    }

    /// The texel value that gives the parameter value `x` (0 for an empty range).
    pub fn texel(&self, x: f32) -> f32 {
        let width = self.range[1] - self.range[0];
        if width == 0.0 { 0.0 } else { (x - self.range[0]) / width }
    }
}

/// A texture channel: one of R, G, B, A (a scalar; grey in a colour slot) or all of RGB.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Channel {
    R,
    G,
    B,
    A,
    Rgb,
}

impl Channel {
    pub const NAMES: &'static [&'static str] = &["R", "G", "B", "A", "Rgb"];
    pub const ALL: [Channel; 5] = [Channel::R, Channel::G, Channel::B, Channel::A, Channel::Rgb];

    /// The channel's index in an RGBA texel; `None` for RGB.
    pub fn index(self) -> Option<u32> {
        match self {
            Channel::R => Some(0),
            Channel::G => Some(1),
            Channel::B => Some(2),
            Channel::A => Some(3),
            Channel::Rgb => None,
        }
    }

    /// The suffix of a texture-read parameter's name: `clay_maps` channel G is `clay_maps_g`.
    pub fn suffix(self) -> &'static str {
        match self {
            Channel::R => "r",
            Channel::G => "g",
            Channel::B => "b",
            Channel::A => "a",
            Channel::Rgb => "rgb",
        }
    }
}

/// A parameter's value; its variant is the parameter's type.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamValue {
    Scalar(f32),
    Rgb([f32; 3]),
}

impl ParamValue {
    pub fn type_name(self) -> &'static str {
        match self {
            ParamValue::Scalar(_) => "f32",
            ParamValue::Rgb(_) => "rgb",
        }
    }

    /// Its numbers: one, or r, g, b.
    pub fn components(&self) -> &[f32] {
        match self {
            ParamValue::Scalar(x) => std::slice::from_ref(x),
            ParamValue::Rgb(c) => c,
        }
    }
}

/// Byte spans of the material's parts in its source file, for diagnostics after `check`.
/// Programmatically built materials have an empty map.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SourceMap {
    pub name: Option<crate::diag::Span>,
    /// One span per layer (coats, then the base).
    pub layers: Vec<crate::diag::Span>,
    /// One span per parameter (its first declaration).
    pub params: Vec<crate::diag::Span>,
    /// Notes `check` has for the author (the coefficients a `Measured` layer derived); they
    /// never make a compilation fail.
    pub notes: Vec<crate::diag::Diagnostic>,
}

/// A material name in CamelCase, as its structs in generated code start (`wet_clay` → `WetClay`).
pub fn camel_case(name: &str) -> String {
    let mut out = String::new();
    for part in name.split('_').filter(|p| !p.is_empty()) {
        let mut chars = part.chars();
        if let Some(first) = chars.next() {
            out.extend(first.to_uppercase());
            out.push_str(chars.as_str());
        }
    }
    out
}

impl Material {
    /// The runtime parameters' default values, in declaration order.
    pub fn default_values(&self) -> Vec<ParamValue> {
        self.params.iter().map(|p| p.default).collect()
    }

    /// The struct name used for the uniform block in generated code (`wet_clay` → `WetClayParams`).
    pub fn params_struct_name(&self) -> String {
        self.struct_name("Params")
    }

    /// The struct name of the texture-read values in generated code (`WetClayTextures`).
    pub fn textures_struct_name(&self) -> String {
        self.struct_name("Textures")
    }

    fn struct_name(&self, suffix: &str) -> String {
        camel_case(&self.name) + suffix
    }

    /// The parameters held in the uniform struct, with their indices in [`Self::params`].
    pub fn uniform_params(&self) -> impl Iterator<Item = (usize, &Param)> {
        self.params.iter().enumerate().filter(|(_, p)| p.source == ParamSource::Uniform)
    }

    /// The parameters read from textures, with their indices in [`Self::params`] and reads.
    pub fn texture_params(&self) -> impl Iterator<Item = (usize, &Param, &TextureRead)> {
        self.params.iter().enumerate().filter_map(|(i, p)| match &p.source {
            ParamSource::Texture(read) => Some((i, p, read)),
            ParamSource::Uniform => None,
        })
    }

    /// The textures the material reads, each once: its parameters' textures in order of first
    /// use, then its normal maps' in layer order. Their bindings follow this order.
    pub fn textures(&self) -> Vec<&str> {
        distinct_textures(&self.params, &self.normals)
    }

    /// The normal map of layer `layer` (coats first, then the base at `coats.len()`).
    pub fn normal_map(&self, layer: usize) -> Option<&NormalMap> {
        self.normals.iter().find(|(l, _)| *l == layer).map(|(_, m)| m)
    }

    /// A layer's name in generated code: `coat0`, `coat1`, …, `base`.
    pub fn layer_name(&self, layer: usize) -> String {
        if layer < self.coats.len() { format!("coat{layer}") } else { "base".to_string() }
    }
}

/// Largest number of coat layers a material may have. The stack is unrolled into straight-line
/// shader code, so this bounds shader size, not correctness.
pub const MAX_COATS: usize = 16;

/// Most runtime parameters a material may declare (one uniform struct member each; 64 members
/// are at most 1 KiB of uniform data).
pub const MAX_PARAMS: usize = 64;

/// Most textures a material may read (each is one binding; wgpu's default limit is 16 sampled
/// textures per shader stage, and image-based lighting needs some of them).
pub const MAX_TEXTURES: usize = 8;

/// F0 of a dielectric interface with relative IOR η: ((η − 1)/(η + 1))² (normal incidence).
pub fn f0_from_ior(ior: f32) -> f32 {
    let r = (ior - 1.0) / (ior + 1.0);
    r * r
}

/// The relative IOR η ≥ 1 whose normal-incidence reflectance is `f0` (inverse of [`f0_from_ior`]).
pub fn ior_from_f0(f0: f32) -> f32 {
    let s = f0.clamp(0.0, 0.999_999).sqrt();
    (1.0 + s) / (1.0 - s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f0_and_ior_round_trip() {
        assert!((f0_from_ior(1.5) - 0.04).abs() < 1e-7);
        assert!((ior_from_f0(0.04) - 1.5).abs() < 1e-5);
    }

    #[test]
    fn params_struct_name_is_camel_case() {
        let m = Material {
            name: "wet_clay_2".into(),
            method: Method::INTERFACED,
            coats: vec![],
            base: Base::Lambert { albedo: Color::Lit([0.5; 3]) },
            params: vec![],
            normals: vec![],
        };
        assert_eq!(m.params_struct_name(), "WetClay2Params");
    }
}
