//! The layering methods: how a stack of coats over a base becomes one BRDF.
//!
//! The stack is known at compile time, so each method is a Rust recursion over the layers that
//! unrolls into straight-line code: the same function produces the CPU value and, run on the
//! naga builder, the body of `<material>_brdf`. Every method goes through [`brdf`], so clay,
//! Disney clear-coat and eight-layer stacks share one code path.
//!
//! * [`Method::Additive`] (Burley 2012; seed 000 §3.0.2): the base at the outer directions plus
//!   one specular lobe per coat, nothing attenuated.
//! * [`Method::WeidlichWilkie`] (seed 000 §3.0.3, eq. 12–19), as the seed writes it. Readings
//!   where the seed is ambiguous (also in README.md):
//!   - eq. 12 evaluates the lower layer at (L′, V) but eq. 13's legend at (L′, V′); we refract
//!     **both** directions (V′), as Weidlich & Wilkie 2007 do, which also keeps f reciprocal;
//!     eq. 15's path length likewise uses n·V′.
//!   - eq. 5 writes Schlick's F with n·V; for a microfacet lobe we use v·h, as the seed's own
//!     source (LearnOpenGL, eq. 2) does; a smooth coat has h = n, so it is n·V there.
//!   - eq. 18–19 multiply "Diffuse × a × f_r" with Diffuse = (1 − F)·OrenNayar: we read them as
//!     eq. 13 with f_r2 = Oren–Nayar, i.e. (1 − F) is T12, applied once, not twice.
//!   - no η² radiance compression and no inter-reflection (faithful; this is why it is measured).
//! * [`Method::Interfaced`] (glazec's default), per coat, top down:
//!   - the interface's own lobe (exact dielectric Fresnel at the microfacet normal,
//!     height-correlated Smith GGX) plus a Kulla–Conty lobe for the light that scatters more
//!     than once between microfacets (E_ms, tabulated), so a rough interface conserves energy;
//!   - transmission T(μ) = 1 − F(μ) + G(μ) − E_ms(μ) (G: the single-scattering lobe's deficit
//!     against a smooth interface; tabulated, `super::tables`); 1 − F(μ) for a smooth coat;
//!   - absorption e^{−τ/μ′} along both refracted paths, μ′ Snell's cosine shortened by the
//!     tabulated path factor of a rough interface; η² radiance compression;
//!   - below the coat, a diffuse body gets f_b + E_b(μi)E_b(μo)R(τ)/(π(1 − ρ̄R(τ))): the series of
//!     internal reflections (TIR included) between the coat and the body, R(τ) and the escape
//!     share E_esc(τ) from slab integrals (smooth) or tables (rough). When the layer below is
//!     itself coated, the series starts from what its first reflection really returns
//!     (`first_pass`): that light leaves concentrated towards the normal. A conductor directly
//!     under the coat gets the **glossy level** (`glossy`, see its essay): a lobe for the light
//!     that leaves near the mirror direction and a separable remainder for the light trapped
//!     by TIR, split by the number of conductor events with statistics from white random walks
//!     (`glazec tables`). A glossy layer deeper down (a coated conductor under further coats)
//!     keeps its lobe: f_b/(1 − √(E k E k)) for the bounces inside the escape cone, widened by
//!     the refraction through a rough coat above (`BLUR_WIDTH`).
//!
//!   Reciprocal, white furnace within 2·10⁻³, exact for a smooth coat over Lambert with
//!   absorption (research/accuracy.md §1.4); measured against the stochastic reference in
//!   `crate::accuracy` (README "Accuracy").

use std::cell::OnceCell;

pub mod environment;
mod glossy;

pub use glossy::{GLOSSY_GRAZING, glossy_coat_transmission, glossy_lobe_normaliser, glossy_lobe_white};

use super::quadrature::{GAUSS_LEGENDRE_4, GAUSS_LEGENDRE_12};
use super::tables::{self, TableId};
use super::terms::*;
use super::{Named, Real, Slot, Vector};
use crate::model::{Approximations, Base, Coat, Color, ConductorFresnel, Lobe, Material, Method, Scalar};

/// Cosines are clamped to at least this before anything divides by them. It keeps f finite at
/// grazing angles and changes nothing above θ = 89.994°.
pub const COS_EPSILON: f32 = 1e-4;

/// The roughness α_g of the Disney clear-coat's Smith term: fixed at 0.25 (Burley 2012;
/// seed 000 §3.0.2).
const GTR1_SMITH_ROUGHNESS: f32 = 0.25;

/// Runtime-parameter values and literal constants, as values of the [`Real`] family.
pub struct Inputs<F: Real> {
    ctx: F::Ctx,
    params: Vec<Slot<F>>,
    /// Per-layer shading normals (coats, then the base), for layers with a normal map.
    normals: Vec<(usize, F::Vec)>,
}

impl<F: Real> Inputs<F> {
    /// `params` holds one value per [`Material::params`] entry, in order.
    pub fn new(ctx: F::Ctx, params: Vec<Slot<F>>) -> Self {
        Inputs { ctx, params, normals: Vec::new() }
    }

    /// The shading normals of layers with a normal map: (layer, unit normal in the frame of
    /// `n`, `v`, `l`); coats are layers 0…, the base is layer `coats.len()`.
    pub fn with_normals(mut self, normals: Vec<(usize, F::Vec)>) -> Self {
        self.normals = normals;
        self
    }

    fn layer_normal(&self, layer: usize) -> Option<F::Vec> {
        self.normals.iter().find(|(l, _)| *l == layer).map(|(_, n)| *n)
    }

    pub fn lit(&self, x: f32) -> F {
        F::constant(self.ctx, x)
    }

    pub fn scalar(&self, s: Scalar) -> F {
        match s {
            Scalar::Lit(x) => self.lit(x),
            Scalar::Param(id) => match self.params[id.0 as usize] {
                Slot::S(x) => x,
                // `check` only binds scalar parameters to scalar slots.
                Slot::V(v) => v.x(),
            },
        }
    }

    pub fn color(&self, c: Color) -> F::Vec {
        match c {
            Color::Lit([r, g, b]) => F::vec3(self.lit(r), self.lit(g), self.lit(b)),
            Color::Param(id) => match self.params[id.0 as usize] {
                Slot::S(x) => x.splat(),
                Slot::V(v) => v,
            },
        }
    }

    fn zero(&self) -> F::Vec {
        self.lit(0.0).splat()
    }
}

/// The BRDF f(l, v) of a material, **without** the cosine, for unit vectors `n`, `v`, `l`
/// (both directions pointing away from the surface). Zero when either lies below the horizon.
pub fn brdf<F: Real>(material: &Material, inputs: &Inputs<F>, n: F::Vec, v: F::Vec, l: F::Vec) -> F::Vec {
    let (coats, body) = expand(material);
    // Each level's normal: its layer's normal map, or the surface normal. (A plastic base expands
    // to a coat and a body: both take the base's map.)
    // Without normal maps every level has the surface normal: no per-level table (this runs for
    // every evaluation on the CPU).
    if inputs.normals.is_empty() {
        let top = Geometry::new(n, v, l, 0);
        return finish_brdf(material, &coats, &body, inputs, &top, (top.raw_n_dot_v, top.raw_n_dot_l));
    }
    let levels: Vec<(F::Vec, bool)> = (0..=coats.len())
        .map(|level| match inputs.layer_normal(level.min(material.coats.len())) {
            Some(mapped) => (mapped.named(&level_name("shading_normal", level)), true),
            None => (n, false),
        })
        .collect();
    let top_normal = if levels[0].1 { facing::<F>(levels[0].0, v, 0) } else { levels[0].0 };
    let surface = levels.iter().any(|&(_, mapped)| mapped).then_some(n);
    let top = Geometry::new(top_normal, v, l, 0).with_levels(std::rc::Rc::from(levels), surface);
    // (The horizon is the surface normal's: a normal map tilts the shading, not the horizon.)
    finish_brdf(material, &coats, &body, inputs, &top, (n.dot(v), n.dot(l)))
}

/// Runs the material's method from the top level and makes f one-sided: zero unless both
/// cosines to the surface normal, `(n·v, n·l)`, are positive.
fn finish_brdf<F: Real>(
    material: &Material,
    coats: &[Coat],
    body: &Body<'_>,
    inputs: &Inputs<F>,
    top: &Geometry<F>,
    (surface_v, surface_l): (F, F),
) -> F::Vec {
    let f = match material.method {
        Method::Additive => additive(coats, body, inputs, top),
        Method::WeidlichWilkie => weidlich_wilkie(coats, body, inputs, top, 0, None),
        Method::Interfaced(approx) => interfaced(coats, body, inputs, top, 0, None, None, false, approx).f,
    };
    // A one-sided BRDF: nothing is reflected from or towards below the horizon.
    let above = surface_v.gt_lit(0.0) & surface_l.gt_lit(0.0);
    F::Vec::select(above, f.named("f"), inputs.zero())
}

/// The reflectance of the stack's mirror (delta) lobe towards `v`: the part of the light that a
/// smooth top coat reflects specularly, which [`brdf`] (a function of two directions) cannot
/// show. Zero for a rough top coat or a bare base. Each method's own Fresnel: exact for
/// `Interfaced`, Schlick's for the seed's methods. Reflections off deeper smooth interfaces
/// (also deltas) are not included.
pub fn mirror_reflectance<F: Real>(material: &Material, inputs: &Inputs<F>, n: F::Vec, v: F::Vec) -> F::Vec {
    let Some(coat) = material.coats.first() else { return inputs.zero() };
    if !matches!(coat.lobe, Lobe::Smooth) {
        return inputs.zero();
    }
    let eta = inputs.scalar(coat.ior);
    let n_dot_v = n.dot(v);
    let reflectance = match material.method {
        Method::Interfaced(approx) => dielectric_fresnel(n_dot_v, eta, approx).splat(),
        Method::Additive | Method::WeidlichWilkie => {
            f_schlick(f0_dielectric(eta).splat(), n_dot_v.at_least(COS_EPSILON))
        }
    };
    F::Vec::select(n_dot_v.gt_lit(0.0), reflectance, inputs.zero())
}

/// The opaque body of a stack after expansion (a `Plastic` base is a GGX coat over Lambert).
enum Body<'m> {
    Lambert(Color),
    OrenNayar(Color, Scalar),
    Eon(Color, Scalar),
    Conductor(Scalar, &'m ConductorFresnel),
}

fn expand(material: &Material) -> (Vec<Coat>, Body<'_>) {
    let mut coats = material.coats.clone();
    let body = match &material.base {
        Base::Lambert { albedo } => Body::Lambert(*albedo),
        Base::OrenNayar { albedo, roughness } => Body::OrenNayar(*albedo, *roughness),
        Base::Eon { albedo, roughness } => Body::Eon(*albedo, *roughness),
        Base::Conductor { roughness, fresnel } => Body::Conductor(*roughness, fresnel),
        Base::Plastic { albedo, roughness, ior } => {
            coats.push(Coat {
                lobe: Lobe::Ggx { roughness: *roughness },
                ior: *ior,
                absorption: Color::Lit([0.0; 3]),
                thickness: Scalar::Lit(0.0),
            });
            Body::Lambert(*albedo)
        }
    };
    (coats, body)
}

/// Cosine below which a mapped normal is bent towards the viewer (see [`facing`]).
const FACING_EPSILON: f32 = 0.05;

/// A normal-mapped shading normal that faces away from the (refracted) view direction `v` shows
/// a facet the viewer cannot see, which renders as black specks on steep bumps; it is bent
/// towards `v` just enough that n·v = ε: n′ = normalize(n + v (ε − n·v)) when n·v < ε (the usual
/// horizon fix for normal maps, cf. Jimenez et al. 2016 on normal/view mismatch).
fn facing<F: Real>(n: F::Vec, v: F::Vec, level: usize) -> F::Vec {
    let deficit = (n.dot(v) * -1.0 + FACING_EPSILON).at_least(0.0);
    (n + v * deficit).normalize().named(&level_name("facing_normal", level))
}

/// Every level's normal and whether it comes from a normal map (see [`brdf`]).
type Levels<F> = std::rc::Rc<[(<F as Real>::Vec, bool)]>;

/// The directions at one level of the stack and the cosines derived from them.
struct Geometry<F: Real> {
    n: F::Vec,
    v: F::Vec,
    l: F::Vec,
    raw_n_dot_v: F,
    raw_n_dot_l: F,
    /// n·v and n·l clamped to ≥ COS_EPSILON, for use in denominators.
    n_dot_v: F,
    n_dot_l: F,
    level: usize,
    half: OnceCell<Half<F>>,
    /// Every level's normal, and whether it comes from a normal map (see [`brdf`]).
    levels: Option<Levels<F>>,
    /// Whether this level's normal comes from a normal map: its BRDF is then zero for
    /// directions below its own horizon, which the surface's horizon does not exclude.
    mapped: bool,
    /// The surface normal (before any normal map), where it differs from `n`.
    surface: Option<F::Vec>,
    /// Only the directional albedos are wanted (image-based lighting, [`environment`]): the
    /// methods skip f itself, which would be dead code in the generated function.
    albedo_only: bool,
}

/// The half vector h = (v + l)/|v + l| at one level, through the quantities the lobes use.
#[derive(Clone, Copy)]
struct Half<F: Real> {
    /// cos θh = n·h.
    n_dot_h: F,
    /// sin²θh = |n × h|², computed directly rather than as 1 − (n·h)², which cancels
    /// catastrophically in f32 at the specular peak (n·h → 1) of a sharp lobe.
    sin2_h: F,
    /// v·h (= l·h).
    v_dot_h: F,
}

/// The name of a value at one level of the stack in generated code: `v` at the top, `layer1_v`
/// under the first coat, and so on (no trailing digits, which naga would suffix with `_`).
fn level_name(base: &str, level: usize) -> String {
    if level == 0 { base.to_string() } else { format!("layer{level}_{base}") }
}

impl<F: Real> Geometry<F> {
    fn new(n: F::Vec, v: F::Vec, l: F::Vec, level: usize) -> Self {
        let raw_n_dot_v = n.dot(v).named(&level_name("n_dot_v", level));
        let raw_n_dot_l = n.dot(l).named(&level_name("n_dot_l", level));
        Geometry {
            n,
            v,
            l,
            raw_n_dot_v,
            raw_n_dot_l,
            n_dot_v: raw_n_dot_v.at_least(COS_EPSILON).named(&level_name("cos_v", level)),
            n_dot_l: raw_n_dot_l.at_least(COS_EPSILON).named(&level_name("cos_l", level)),
            level,
            half: OnceCell::new(),
            levels: None,
            mapped: false,
            surface: None,
            albedo_only: false,
        }
    }

    /// The geometry of an albedo-only evaluation ([`environment`]): no light direction, so l = v
    /// with the very same values (the generated code computes each cosine once, and term calls
    /// on the light's side are the view's).
    fn albedo_only(n: F::Vec, v: F::Vec, level: usize) -> Self {
        let raw_n_dot_v = n.dot(v).named(&level_name("n_dot_v", level));
        let n_dot_v = raw_n_dot_v.at_least(COS_EPSILON).named(&level_name("cos_v", level));
        Geometry {
            n,
            v,
            l: v,
            raw_n_dot_v,
            raw_n_dot_l: raw_n_dot_v,
            n_dot_v,
            n_dot_l: n_dot_v,
            level,
            half: OnceCell::new(),
            levels: None,
            mapped: false,
            surface: None,
            albedo_only: true,
        }
    }

    /// For a level whose normal comes from a normal map, the light's cosine to that normal over
    /// its cosine to the surface normal, max(n_s·l, 0)/max(n·l, ε): the mapped facet receives
    /// irradiance by its own cosine while `<material>_eval` multiplies by the surface's. This is
    /// the shading-normal BRDF of Veach 1997 §5.3 (not reciprocal, as no normal map is); it is
    /// what makes a bumpy Lambertian body look bumpy at all (its f alone is constant).
    fn shading_cosine_ratio(&self) -> Option<F> {
        if !self.mapped {
            return None;
        }
        let surface = self.surface?;
        Some(
            (self.raw_n_dot_l.at_least(0.0) / surface.dot(self.l).at_least(COS_EPSILON))
                .named(&level_name("shading_ratio", self.level)),
        )
    }

    fn with_levels(mut self, levels: std::rc::Rc<[(F::Vec, bool)]>, surface: Option<F::Vec>) -> Self {
        self.mapped = levels.get(self.level).is_some_and(|&(_, mapped)| mapped);
        self.levels = Some(levels);
        self.surface = surface;
        self
    }

    /// The same directions seen by the layer of level `level` (its normal), for methods that
    /// evaluate every layer at the outer directions (`Additive`); `self` if it has no map.
    fn facing_level(&self, level: usize) -> Option<Geometry<F>> {
        let &(n, mapped) = self.levels.as_ref()?.get(level)?;
        if !mapped || level == self.level {
            return None;
        }
        let mut g = Geometry::new(n, self.v, self.l, self.level);
        g.mapped = true;
        g.surface = self.surface;
        Some(g)
    }

    fn v_dot_l(&self) -> F {
        self.v.dot(self.l)
    }

    /// The half vector's cosines, computed once per level.
    fn half(&self) -> Half<F> {
        *self.half.get_or_init(|| {
            let h = half_vector::<F>(self.v, self.l).named(&level_name("h", self.level));
            let n_cross_h = self.n.cross(h).named(&level_name("n_cross_h", self.level));
            Half { n_dot_h: self.n.dot(h), sin2_h: n_cross_h.dot(n_cross_h), v_dot_h: self.v.dot(h) }
        })
    }

    /// The directions one layer down, under an interface of relative IOR `eta`.
    fn refracted(&self, eta: F) -> Geometry<F> {
        let level = self.level + 1;
        let v = refract_down(self.v, self.n, eta).named(&level_name("v", level));
        if self.albedo_only {
            return Geometry::albedo_only(self.n, v, level);
        }
        let l = refract_down(self.l, self.n, eta).named(&level_name("l", level));
        let Some(levels) = &self.levels else { return Geometry::new(self.n, v, l, level) };
        let n = match levels.get(level) {
            Some(&(n, true)) => facing::<F>(n, v, level),
            Some(&(n, false)) => n,
            None => self.n,
        };
        Geometry::new(n, v, l, level).with_levels(levels.clone(), self.surface)
    }
}

fn additive<F: Real>(coats: &[Coat], body: &Body<'_>, inputs: &Inputs<F>, g: &Geometry<F>) -> F::Vec {
    // Every layer at the outer directions, each with its own normal where it has a map.
    let base_g = g.facing_level(coats.len());
    let mut f = base_brdf(body, inputs, base_g.as_ref().unwrap_or(g), None, None).named("f_base");
    for (k, coat) in coats.iter().enumerate() {
        let coat_g = g.facing_level(k);
        if let Some(lobe) = seed_lobe(&coat.lobe, inputs.scalar(coat.ior), inputs, coat_g.as_ref().unwrap_or(g)) {
            f = f + lobe.specular;
        }
    }
    f
}

/// A coat's specular lobe as the seed computes it (Schlick F, Schlick-GGX G).
struct SeedLobe<F: Real> {
    specular: F::Vec,
    fresnel: F::Vec,
    distribution: F,
    shadowing: F,
}

/// The seed's Cook–Torrance coat lobe (seed 000 §3.0.1–3.0.2), `None` for a smooth coat.
fn seed_lobe<F: Real>(lobe: &Lobe, eta: F, inputs: &Inputs<F>, g: &Geometry<F>) -> Option<SeedLobe<F>> {
    let name = |base| level_name(base, g.level);
    let (roughness, distribution) = match lobe {
        Lobe::Smooth => return None,
        Lobe::Ggx { roughness } => {
            let r = inputs.scalar(*roughness);
            (r, d_ggx(g.half().n_dot_h, g.half().sin2_h, r * r))
        }
        Lobe::Gtr1 { roughness } => {
            let r = inputs.scalar(*roughness);
            (inputs.lit(GTR1_SMITH_ROUGHNESS), d_gtr1(g.half().n_dot_h, g.half().sin2_h, r * r))
        }
    };
    let distribution = distribution.named(&name("d"));
    let shadowing = g_smith_schlick_ggx(g.n_dot_v, g.n_dot_l, roughness).named(&name("g"));
    let fresnel = f_schlick(f0_dielectric(eta).splat(), g.half().v_dot_h).named(&name("fresnel"));
    let specular = f_cook_torrance(distribution, shadowing, fresnel, g.n_dot_v, g.n_dot_l).named(&name("specular"));
    Some(SeedLobe { specular, fresnel, distribution, shadowing })
}

/// The seed's coat lobe without its Fresnel factor, D·G/(4 μv μl), for unit directions in the
/// frame of `n` (zero below the horizon and for a smooth coat): what `glazec tables` integrates
/// into the seed lobes' split-sum DFG (`environment`), so that image-based lighting weighs the
/// lobe the shaders evaluate.
pub fn seed_lobe_white(lobe: &Lobe, n: glam::Vec3, v: glam::Vec3, l: glam::Vec3) -> f32 {
    if n.dot(v) <= 0.0 || n.dot(l) <= 0.0 {
        return 0.0;
    }
    let inputs = Inputs::<f32>::new((), Vec::new());
    let g = Geometry::new(n, v, l, 0);
    // (The IOR only sets the Fresnel factor, which is left out.)
    seed_lobe(lobe, 1.5, &inputs, &g)
        .map_or(0.0, |seed| f_cook_torrance(seed.distribution, seed.shadowing, glam::Vec3::ONE, g.n_dot_v, g.n_dot_l).x)
}

fn weidlich_wilkie<F: Real>(
    coats: &[Coat],
    body: &Body<'_>,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    k: usize,
    n_medium: Option<F>,
) -> F::Vec {
    let Some(coat) = coats.get(k) else {
        return base_brdf(body, inputs, g, n_medium, None).named(&level_name("f_base", g.level));
    };
    let eta = inputs.scalar(coat.ior);
    let (f_top, fresnel, shadowing) = match seed_lobe(&coat.lobe, eta, inputs, g) {
        Some(lobe) => (lobe.specular, lobe.fresnel, lobe.shadowing),
        // A smooth interface: its mirror lobe is a delta (zero for point lights), h = n, G = 1.
        None => (inputs.zero(), f_schlick(f0_dielectric(eta).splat(), g.n_dot_v), inputs.lit(1.0)),
    };
    let name = |base| level_name(base, k);
    let t12 = fresnel.one_minus().named(&name("transmission"));
    let below = g.refracted(eta);
    let sigma_a = inputs.color(coat.absorption);
    let thickness = inputs.scalar(coat.thickness);
    // No absorption (σa = 0 or d = 0) is e^0 = 1: skip the call.
    let absorption = if sigma_a.is_known_zero() || thickness.splat().is_known_zero() {
        inputs.lit(1.0).splat()
    } else {
        absorption_ww(sigma_a, thickness, below.n_dot_l, below.n_dot_v).named(&name("absorption"))
    };
    let inner = ww_inner_reflection(shadowing, t12).named(&name("inner"));
    let n_below = Some(n_medium.map_or(eta, |n| n * eta));
    let f_below = weidlich_wilkie(coats, body, inputs, &below, k + 1, n_below);
    ww_layer::<F>(f_top, t12, absorption, inner, f_below).named(&name("f"))
}

/// What the interfaced method knows about the layer under a coat, at that layer's directions.
struct Level<F: Real> {
    /// f at the level's (refracted) directions.
    f: F::Vec,
    /// Its directional and mean albedos, when the coat above needs them.
    albedo: Option<Albedo<F>>,
    /// A bare conductor: its reflection stays a lobe (see `interfaced_glossy_under`).
    glossy: bool,
    /// The GGX α of that lobe (a bare conductor only).
    alpha: Option<F>,
    /// How much more easily than diffuse light the light this level sends up escapes the coats
    /// above it (see [`first_pass`]); 1 for the body.
    boost: F,
    /// Its top coat's transmission T(μ) towards l and v (`None` for the body).
    transmission: Option<(F, F)>,
}

/// Directional albedos towards l and v, and the hemispherical mean.
#[derive(Clone, Copy)]
struct Albedo<F: Real> {
    e_l: F::Vec,
    e_v: F::Vec,
    mean: F::Vec,
}

/// How much a rough coat widens a conductor's lobe under it: α += BLUR_WIDTH · |1 − 1/η| α_coat.
/// A facet tilted by θm refracts a ray by about (1 − 1/η) θm (Walter et al. 2007, the
/// refraction Jacobian at normal incidence). The light crosses the coat twice, through
/// independent facets, so the two deviations add in quadrature: √2 (1 − 1/η) α_coat in
/// direction. A GGX lobe of width α in half-vector slope reflects into 2α in direction, so that
/// spread is (1/√2)(1 − 1/η) α_coat in the conductor's α. GGX slopes are heavy-tailed, so the
/// added width adds to the conductor's own linearly rather than in quadrature (Belcour 2018 adds
/// variances). Against the reference (standard set, copper under coats of roughness 0.5) this
/// gives a lobe error of 9–14%; the earlier ½ (a guess) gave 14–20%.
const BLUR_WIDTH: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// The blur a coat of roughness `roughness` (α = r²) and relative IOR `eta` adds to the `blur`
/// of the coats above it (see [`BLUR_WIDTH`]); a smooth coat adds none.
fn coat_blur<F: Real>(roughness: Option<F>, eta: F, blur: Option<F>, k: usize) -> Option<F> {
    let Some(r) = roughness else { return blur };
    // |1 − 1/η|: a coat optically thinner than the medium above (η < 1) spreads rays too (and a
    // negative width would make α negative).
    let spread = eta.recip().one_minus().abs();
    let added = (spread * r.sq() * BLUR_WIDTH).named(&level_name("blur", k));
    Some(blur.map_or(added, |b| b + added))
}

/// The interfaced method from coat `k` down. `blur` is the GGX α that rough coats above add to a
/// conductor's lobe (see [`BLUR_WIDTH`]).
#[allow(clippy::too_many_arguments)]
fn interfaced<F: Real>(
    coats: &[Coat],
    body: &Body<'_>,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    k: usize,
    n_medium: Option<F>,
    blur: Option<F>,
    want_albedo: bool,
    approx: Approximations,
) -> Level<F> {
    let Some(coat) = coats.get(k) else {
        let f = if g.albedo_only {
            inputs.zero()
        } else {
            base_brdf(body, inputs, g, n_medium, blur).named(&level_name("f_base", g.level))
        };
        let albedo = want_albedo.then(|| body_albedo(body, inputs, g, n_medium, blur));
        let alpha = match body {
            Body::Conductor(roughness, _) => Some(conductor_alpha(inputs.scalar(*roughness), blur, g.level)),
            _ => None,
        };
        return Level { f, albedo, glossy: alpha.is_some(), alpha, boost: inputs.lit(1.0), transmission: None };
    };
    // A conductor directly under this coat: the glossy level.
    if let (None, Body::Conductor(roughness, fresnel)) = (coats.get(k + 1), body) {
        let conductor = (*roughness, *fresnel);
        return glossy::glossy_level(coat, conductor, inputs, g, k, n_medium, blur, want_albedo, approx);
    }
    let name = |base| level_name(base, k);
    let eta = inputs.scalar(coat.ior);
    let tau = (inputs.color(coat.absorption) * inputs.scalar(coat.thickness)).named(&name("tau"));
    let interface = CoatInterface::new(&coat.lobe, eta, inputs, k, approx);
    let f_top = if g.albedo_only {
        inputs.zero()
    } else {
        (interfaced_lobe(&coat.lobe, eta, inputs, g, approx) + interface.restored_lobe(g)).named(&name("specular"))
    };
    let t_l = interface.transmission(g.raw_n_dot_l, "l");
    let t_v = interface.transmission(g.raw_n_dot_v, "v");
    let below = g.refracted(eta);
    // A clear slab (τ = 0) transmits everything: e^0 = 1, so the calls are skipped.
    let (a_l, a_v) = if tau.is_known_zero() {
        (inputs.lit(1.0).splat(), inputs.lit(1.0).splat())
    } else {
        let path_l = interface.path_cosine(g.raw_n_dot_l, below.n_dot_l, "l");
        let path_v = interface.path_cosine(g.raw_n_dot_v, below.n_dot_v, "v");
        (
            slab_transmittance(tau, path_l).named(&name("absorb_l")),
            slab_transmittance(tau, path_v).named(&name("absorb_v")),
        )
    };
    let n_below = Some(n_medium.map_or(eta, |n| n * eta));
    let blur_below = coat_blur(interface.roughness, eta, blur, k);
    let lower = interfaced(coats, body, inputs, &below, k + 1, n_below, blur_below, true, approx);
    let albedo = lower.albedo.unwrap_or_else(|| Albedo { e_l: inputs.zero(), e_v: inputs.zero(), mean: inputs.zero() });
    let (r_return, e_escape) = interface.slab(tau);
    // The clear slab's (R(0), E_esc(0)), built when first needed.
    let clear = OnceCell::new();
    let clear = || *clear.get_or_init(|| interface.slab(inputs.zero()));
    let first = (!lower.glossy).then(|| match (coats.get(k + 1), body) {
        (None, Body::Eon(rho, r)) => eon_first_pass(&interface, (*rho, *r), g, &below, &clear, inputs),
        _ => first_pass(coats, k, &interface, &lower, &albedo, (t_l, t_v), &clear, inputs),
    });
    let boost = first.as_ref().map_or(inputs.lit(1.0), |p| p.boost);
    let f_under: F::Vec = if g.albedo_only {
        inputs.zero()
    } else if lower.glossy {
        let k_l = (a_l * a_l * t_l.one_minus()).named(&name("inner_l"));
        let k_v = (a_v * a_v * t_v.one_minus()).named(&name("inner_v"));
        let glossy = interfaced_glossy_under::<F>(lower.f, albedo.e_l, k_l, albedo.e_v, k_v);
        glossy
            + trapped(&interface, &below, &albedo, lower.alpha, (r_return, clear().0), inputs).named(&name("trapped"))
    } else if let Some(first) = &first {
        // The series starts from what the first pass returns, E·c (c = 1 for a diffusing body),
        // and on the viewer's side is divided by the return factor of diffuse light through the
        // escape cone, so that what returns eventually escapes (reciprocal: symmetric in l, v).
        let e_v = albedo.e_v * first.return_v / first.return_mean.max(first.return_l.min(first.return_v));
        interfaced_diffuse_under::<F>(lower.f, albedo.e_l * first.return_l, e_v, albedo.mean, r_return)
    } else {
        unreachable!("a layer that is not glossy has its first pass")
    };
    let f = if g.albedo_only {
        inputs.zero()
    } else {
        interfaced_layer(f_top, t_l, t_v, a_l, a_v, f_under.named(&name("under")), eta).named(&name("f"))
    };
    let albedo = want_albedo.then(|| {
        let directional =
            |t: F, a: F::Vec, e: F::Vec, escape: Option<F::Vec>, back: Option<F::Vec>| match (escape, back) {
                (Some(escape), Some(back)) => {
                    interfaced_albedo_dir(t, a, e, albedo.mean, r_return, e_escape, escape, back)
                }
                _ => interfaced_albedo_glossy::<F>(t, a, e),
            };
        let e_l =
            directional(t_l, a_l, albedo.e_l, first.as_ref().map(|p| p.escape_l), first.as_ref().map(|p| p.return_l))
                .named(&name("albedo_l"));
        let e_v =
            directional(t_v, a_v, albedo.e_v, first.as_ref().map(|p| p.escape_v), first.as_ref().map(|p| p.return_v))
                .named(&name("albedo_v"));
        let e_escape_clear = clear().1.x();
        let mean = interfaced_albedo(eta, e_escape_clear, e_escape, r_return, albedo.mean).named(&name("rho"));
        Albedo { e_l, e_v, mean }
    });
    Level { f, albedo, glossy: lower.glossy, alpha: lower.alpha, boost, transmission: Some((t_l, t_v)) }
}

/// How the first reflection off the layer under coat `k` differs from a diffusing body's, per
/// light and view direction: `escape_*` scales the share of it that leaves through the coat at
/// once, `return_*` the share the coat sends back down (both 1 for a diffusing body, whose light
/// leaves the way [`interfaced_diffuse_under`]'s series assumes).
struct FirstPass<F: Real> {
    escape_l: F::Vec,
    escape_v: F::Vec,
    return_l: F::Vec,
    return_v: F::Vec,
    /// The return factor of diffuse light seen through the escape cone (at its mean cosine,
    /// with the layer's mean albedo); ≥ 10⁻³.
    return_mean: F::Vec,
    /// T′(μ̄c)/⟨T′⟩ times the layer's own boost: how concentrated towards the normal the light
    /// leaving this coat's level is (handed to the coat above).
    boost: F,
}

/// glazec's interfaced layering, the first pass out of a coated layer. A coated layer below (coat
/// `k + 1` over something) reflects part of the light specularly (1 − T′(μ′), which leaves
/// through coat `k` with its transmission T(μ)) and sends the rest up through coat `k + 1` with a
/// distribution ∝ T′(w) — concentrated towards the normal, so more of it escapes coat `k` than of
/// diffuse light: the share Y ≈ E_esc(0)·b, b = T′(μ̄c)/⟨T′⟩ times the same factor of the coats
/// further down, μ̄c the mean cosine of coat `k`'s escape cone. The first pass then escapes
/// ξ = [(1 − T′)T + (E − (1 − T′))Y]/E and returns 1 − ξ, against E_esc(0) and R(0) = 1 − E_esc(0)
/// for diffuse light. Treating that light as diffuse counted part of it twice (energy gains of up
/// to 16% for sixteen coats, README "Stability"); compounding b down the stack over-corrects
/// deep stacks instead (a white stack of sixteen coats reflects 0.47–0.76).
/// Guards: the return factor is clamped to [0, 1] (never more than a diffusing body returns),
/// ξ to [0, 1], E ≥ 10⁻⁶, R(0) ≥ 10⁻⁴, E_esc(0) ≥ 10⁻⁴.
#[allow(clippy::too_many_arguments)]
fn first_pass<F: Real>(
    coats: &[Coat],
    k: usize,
    interface: &CoatInterface<'_, F>,
    lower_level: &Level<F>,
    albedo: &Albedo<F>,
    (t_l, t_v): (F, F),
    clear: &dyn Fn() -> (F::Vec, F::Vec),
    inputs: &Inputs<F>,
) -> FirstPass<F> {
    let one = inputs.lit(1.0).splat();
    let (Some(next), Some((t_below_l, t_below_v))) = (coats.get(k + 1), lower_level.transmission) else {
        return FirstPass {
            escape_l: one,
            escape_v: one,
            return_l: one,
            return_v: one,
            return_mean: one,
            boost: inputs.lit(1.0),
        };
    };
    let name = |base: &str| level_name(base, k);
    let lower = CoatInterface::new(&next.lobe, inputs.scalar(next.ior), inputs, k + 1, interface.approx);
    let (r_clear, e_clear) = clear();
    let (r_clear, e_clear) = (r_clear.x(), e_clear.x());
    let mu_mean = interface.escape_cone_mean_cosine();
    let t_cone_below = lower.transmission(mu_mean, "cone");
    // Coats further down concentrate the light further (their boost, handed up).
    let boost =
        (t_cone_below / lower.transmission_hemispherical().at_least(1e-4) * lower_level.boost).named(&name("boost"));
    let shaped = (e_clear * boost).clamp(0.0, 1.0).named(&name("first_escape_diffuse"));
    // ξ for light reflected with albedo `e`, of which 1 − T′ (`below_transmission`) specularly,
    // and escaping coat k with transmission `t` at the mirror direction.
    let shares = |e: F::Vec, below_transmission: F, t: F, side: &str| {
        let specular = below_transmission.one_minus();
        let e_safe = e.max(inputs.lit(1e-6).splat());
        let escaped = (specular * t).splat() + (e - specular.splat()).max(inputs.zero()) * shaped;
        let xi = (escaped / e_safe).max(inputs.zero()).min(one);
        let escape = (xi / e_clear.at_least(1e-4)).named(&name(&format!("first_escape_{side}")));
        let back = first_return(xi, r_clear, inputs).named(&name(&format!("first_return_{side}")));
        (escape, back)
    };
    let (escape_l, return_l) = shares(albedo.e_l, t_below_l, t_l, "l");
    let (escape_v, return_v) = shares(albedo.e_v, t_below_v, t_v, "v");
    // At the cone's mean cosine: the outside cosine √(1 − η²(1 − μ̄c²)) and coat k's
    // transmission there.
    let mu_outside = (interface.eta.sq() * mu_mean.sq().one_minus()).one_minus().at_least(0.0).sqrt();
    let (_, return_mean) = shares(albedo.mean, t_cone_below, interface.transmission(mu_outside, "cone"), "cone");
    let return_mean = return_mean.max(inputs.lit(1e-3).splat());
    FirstPass { escape_l, escape_v, return_l, return_v, return_mean, boost }
}

/// The first pass out of an EON body (Portsmouth et al. 2025) under coat `k`. EON's
/// multiple-scattering lobe sends light in proportion to 1 − E_FON(μₒ), which is largest
/// towards the normal, so more of the first reflection leaves through the escape cone than of
/// diffuse light (treating it as diffuse made a water-coated EON 0.011 too bright at normal
/// incidence; README "Accuracy"). Of the body's albedo E(μ) = ρE_FON(μ) + ρ_ms(1 − E_FON(μ)),
/// the FON part is taken to leave like diffuse light and the multiple-scattering part with the
/// cone's weight for its shape, `eon_escape_shape_exact` s (of the smooth interface, tabulated
/// over η; for a rough coat an approximation): escape factor x(μ) = 1 + ρ_ms(1 − E_FON(μ))(s − 1)/E(μ), return factor
/// (1 − x E_esc(0))/R(0) clamped to [0, 1] (R(0) = 1 − E_esc(0): a white body still returns
/// everything, E = 1). The return factor at the cone's mean cosine normalises the viewer's side
/// as in [`first_pass`]. Guards: E ≥ 10⁻⁶, R(0) ≥ 10⁻⁴, the return at the mean ≥ 10⁻³.
fn eon_first_pass<F: Real>(
    interface: &CoatInterface<'_, F>,
    (albedo_color, roughness): (Color, Scalar),
    above: &Geometry<F>,
    below: &Geometry<F>,
    clear: &dyn Fn() -> (F::Vec, F::Vec),
    inputs: &Inputs<F>,
) -> FirstPass<F> {
    let name = |base: &str| level_name(base, below.level);
    let (rho, r) = (inputs.color(albedo_color), inputs.scalar(roughness));
    let (r_clear, e_clear) = clear();
    let (r_clear, e_clear) = (r_clear.x(), e_clear.x());
    let one = inputs.lit(1.0).splat();
    let shape = tables::lookup(TableId::EonEscapeShape, &[interface.eta]).named(&name("eon_escape_shape"));
    let rho_ms = eon_rho_ms(rho, r).named(&name("rho_ms"));
    let factors = |mu: F, side: &str| {
        let e = albedo_eon(rho, r, mu);
        let spread = rho_ms * e_fon(mu, r).one_minus();
        let escape = (one + spread * (shape - 1.0) / e.max(inputs.lit(1e-6).splat()))
            .named(&name(&format!("first_escape_{side}")));
        let back = first_return(escape * e_clear, r_clear, inputs).named(&name(&format!("first_return_{side}")));
        (escape, back)
    };
    // A rough coat spreads the refracted light: its effective cosine (the path factor's) stands
    // for the direction of incidence on the body.
    let mu_l = interface.path_cosine(above.raw_n_dot_l, below.n_dot_l, "l");
    let mu_v = interface.path_cosine(above.raw_n_dot_v, below.n_dot_v, "v");
    let (escape_l, return_l) = factors(mu_l, "l");
    let (escape_v, return_v) = factors(mu_v, "v");
    let mu_mean = interface.escape_cone_mean_cosine();
    let (_, return_mean) = factors(mu_mean, "cone");
    let return_mean = return_mean.max(inputs.lit(1e-3).splat());
    FirstPass { escape_l, escape_v, return_l, return_v, return_mean, boost: inputs.lit(1.0) }
}

/// The light a glossy body under a coat sends outside the escape cone (`trapped_lobe`);
/// `r_clear` is the clear slab's return R(0).
fn trapped<F: Real>(
    interface: &CoatInterface<'_, F>,
    below: &Geometry<F>,
    albedo: &Albedo<F>,
    alpha: Option<F>,
    (r_return, r_clear): (F::Vec, F::Vec),
    inputs: &Inputs<F>,
) -> F::Vec {
    let Some(alpha) = alpha else { return inputs.zero() };
    let name = |base: &str| level_name(base, below.level);
    let eta = interface.eta;
    let mu_c = escape_cone_cosine(eta).named(&name("mu_c"));
    let p_l = trapped_share(below.n_dot_l, mu_c, alpha).named(&name("trapped_l"));
    let p_v = trapped_share(below.n_dot_v, mu_c, alpha).named(&name("trapped_v"));
    // The round trip of trapped light: R(τ)/R(0), the absorption of the slab's diffuse return.
    let round_trip = r_return / r_clear.max(inputs.lit(1e-4).splat());
    let q = trapped_escape(mu_c, alpha).named(&name("trapped_escape"));
    let lobe = trapped_lobe(albedo.e_l, p_l, albedo.e_v, p_v, mu_c, round_trip, albedo.mean, q);
    // Without total internal reflection (η ≤ 1) nothing is trapped.
    F::Vec::select(mu_c.gt_lit(0.0), lobe, inputs.zero())
}

/// A coat's interface as the interfaced method sees it: smooth (exact Fresnel, slab integrals by
/// quadrature) or rough (tabulated: `crate::math::tables`).
struct CoatInterface<'i, F: Real> {
    eta: F,
    /// `None` for a smooth coat.
    roughness: Option<F>,
    inputs: &'i Inputs<F>,
    level: usize,
    approx: Approximations,
}

impl<'i, F: Real> CoatInterface<'i, F> {
    fn new(lobe: &Lobe, eta: F, inputs: &'i Inputs<F>, k: usize, approx: Approximations) -> Self {
        // A literal roughness of 0 is a smooth interface. (A runtime roughness always takes the
        // tabulated path, whose r = 0 nodes are the smooth interface, so the CPU and the shader
        // evaluate the same formula.)
        let roughness = match lobe {
            Lobe::Smooth | Lobe::Ggx { roughness: Scalar::Lit(0.0) } | Lobe::Gtr1 { roughness: Scalar::Lit(0.0) } => {
                None
            }
            Lobe::Ggx { roughness } | Lobe::Gtr1 { roughness } => Some(inputs.scalar(*roughness)),
        };
        CoatInterface { eta, roughness, inputs, level: k + 1, approx }
    }

    fn name(&self, base: &str) -> String {
        level_name(base, self.level)
    }

    /// The mean cosine of the escape cone seen from inside, weighted by projected solid angle:
    /// (2/3)(1 − μc³)/(1 − μc²) with μc = √(1 − 1/η²) (2/3 without TIR). Guard: 1 − μc² ≥ 10⁻⁶.
    fn escape_cone_mean_cosine(&self) -> F {
        let mu_c = escape_cone_cosine(self.eta);
        ((mu_c * mu_c * mu_c).one_minus() / mu_c.sq().one_minus().at_least(1e-6) * (2.0 / 3.0)).clamp(0.0, 1.0)
    }

    /// The tables cover η ∈ [1, 3]. A rough coat of lower relative IOR (optically thinner than
    /// the medium above it) uses the smooth interface's transmission, path and slab terms
    /// instead (its own lobe stays rough): outside their range the tables would give a
    /// hemispherical transmittance above η², i.e. a negative internal reflection. A runtime η
    /// selects between both.
    fn unless_below_one<T>(&self, smooth: impl FnOnce() -> T, rough: T, select: fn(F::Bool, T, T) -> T) -> T {
        match self.eta.known() {
            Some(eta) if eta < 1.0 => smooth(),
            Some(_) => rough,
            None => select(self.eta.lt_lit(1.0), smooth(), rough),
        }
    }

    /// T(μ): the share of light from above at cosine μ that enters the coat. Rough:
    /// T = 1 − F + G − E_ms (single-scattering deficit and multiple-scattering share, tabulated).
    fn transmission(&self, mu: F, side: &str) -> F {
        let name = self.name(&format!("transmit_{side}"));
        let smooth =
            dielectric_fresnel(mu, self.eta, self.approx).named(&self.name(&format!("fresnel_{side}"))).one_minus();
        match self.roughness {
            None => smooth.named(&name),
            Some(r) => {
                let deficit = tables::lookup(TableId::CoatDeficit, &[mu, r, self.eta]);
                let extra = self.extra(mu, r).named(&self.name(&format!("restored_{side}")));
                let rough = (smooth + deficit - extra).clamp(0.0, 1.0);
                self.unless_below_one(|| smooth, rough, F::select).named(&name)
            }
        }
    }

    /// E_ms(μ): the reflection the single-scattering lobe misses.
    fn extra(&self, mu: F, r: F) -> F {
        tables::lookup(TableId::CoatExtra, &[mu, r, self.eta])
    }

    /// ⟨T⟩ for either kind of interface.
    fn transmission_hemispherical(&self) -> F {
        match self.roughness {
            None => tables::lookup(TableId::FresnelTransmitAvg, &[self.eta]),
            Some(r) => self.transmission_avg(r),
        }
    }

    /// ⟨T⟩: the coat's hemispherical transmittance from above, consistent with
    /// [`Self::transmission`] (the averages of the same interpolated curves).
    fn transmission_avg(&self, r: F) -> F {
        let smooth = tables::lookup(TableId::FresnelTransmitAvg, &[self.eta]);
        let deficit = tables::lookup(TableId::CoatDeficitAvg, &[r, self.eta]);
        let extra = tables::lookup(TableId::CoatExtraAvg, &[r, self.eta]);
        (smooth + deficit - extra).named(&self.name("transmit_avg"))
    }

    /// The cosine along which light entering at outer cosine `mu` (refracted cosine
    /// `mu_refracted`) is absorbed: Snell's for a smooth coat, shortened by the tabulated path
    /// factor for a rough one.
    fn path_cosine(&self, mu: F, mu_refracted: F, side: &str) -> F {
        match self.roughness {
            None => mu_refracted,
            Some(r) => {
                let q = tables::lookup(TableId::CoatPath, &[mu, r, self.eta]);
                self.unless_below_one(|| mu_refracted, mu_refracted / q, F::select)
                    .named(&self.name(&format!("path_cos_{side}")))
            }
        }
    }

    /// The multiple-scattering reflection that the coat's single-scattering lobe misses, as a
    /// Kulla–Conty lobe.
    fn restored_lobe(&self, g: &Geometry<F>) -> F::Vec {
        let Some(r) = self.roughness.filter(|_| !self.approx.single_scattering) else { return self.inputs.zero() };
        let e_l = self.extra(g.raw_n_dot_l, r).named(&self.name("restored_l"));
        let e_v = self.extra(g.raw_n_dot_v, r).named(&self.name("restored_v"));
        let e_avg = tables::lookup(TableId::CoatExtraAvg, &[r, self.eta]);
        multiple_scattering_lobe(e_l, e_v, e_avg).splat()
    }

    /// (R(τ), E_esc(τ)) of the coat's slab.
    fn slab(&self, tau: F::Vec) -> (F::Vec, F::Vec) {
        let smooth = || (slab_return(self.eta, tau), slab_escape(self.eta, tau));
        let (r_return, e_escape) = match self.roughness {
            None => smooth(),
            Some(r) => {
                // Both tables are normalised by the internal transmittance ⟨T_int⟩ = ⟨T⟩/η²,
                // so both are exactly 1 for a clear slab (τ = 0): no lookup needed then.
                let scale = self.transmission_avg(r) / self.eta.sq();
                let per_channel = |id: TableId| {
                    if tau.is_known_zero() {
                        return scale.splat();
                    }
                    let at = |t: F| tables::lookup(id, &[t, r, self.eta]);
                    F::vec3(at(tau.x()), at(tau.y()), at(tau.z())) * scale
                };
                // Guard: R(τ) → 0 for a thick slab, where 1 − (interpolated ratio) may round to
                // −10⁻⁸; a reflectance is ≥ 0.
                let zero = self.inputs.zero();
                let r_return = per_channel(TableId::CoatReturn).one_minus().max(zero);
                let rough = (r_return, per_channel(TableId::CoatEscape));
                let pick = |c: F::Bool, a: (F::Vec, F::Vec), b: (F::Vec, F::Vec)| {
                    (F::Vec::select(c, a.0, b.0), F::Vec::select(c, a.1, b.1))
                };
                self.unless_below_one(smooth, rough, pick)
            }
        };
        (r_return.named(&self.name("r_return")), e_escape)
    }
}

/// A coat's own reflection lobe in the interfaced method: exact dielectric Fresnel at the
/// microfacet normal and the exact height-correlated Smith term. Zero for a smooth coat (a delta
/// lobe that point lights cannot see).
fn interfaced_lobe<F: Real>(
    lobe: &Lobe,
    eta: F,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    approx: Approximations,
) -> F::Vec {
    let (distribution, alpha_g) = match lobe {
        Lobe::Smooth => return inputs.zero(),
        Lobe::Ggx { roughness } => {
            let r = inputs.scalar(*roughness);
            (d_ggx(g.half().n_dot_h, g.half().sin2_h, r * r), r * r)
        }
        Lobe::Gtr1 { roughness } => {
            let r = inputs.scalar(*roughness);
            (d_gtr1(g.half().n_dot_h, g.half().sin2_h, r * r), inputs.lit(GTR1_SMITH_ROUGHNESS))
        }
    };
    let name = |base| level_name(base, g.level);
    let distribution = distribution.named(&name("d"));
    let shadowing = g_smith_ggx_correlated(g.n_dot_v, g.n_dot_l, alpha_g).named(&name("g"));
    let microfacet = || dielectric_fresnel(g.half().v_dot_h, eta, approx);
    // A coat optically thinner than the medium above (η < 1) keeps its rough lobe but takes the
    // smooth interface's transmission 1 − F(μ) (the tables stop at η = 1; see
    // `CoatInterface::unless_below_one`). Near the critical angle, facets tilted past it reflect
    // totally, so a lobe with the microfacet Fresnel F(v·h) reflects more than F(μ) and the two
    // together gained up to 14% energy. With min(F(n·v), F(n·l)) instead (symmetric, so
    // reciprocal) the lobe's albedo is at most F(μ) times the white lobe's, ≤ F(μ): no gain.
    let macro_surface = || {
        let f_v = dielectric_fresnel(g.n_dot_v, eta, approx);
        let f_l = dielectric_fresnel(g.n_dot_l, eta, approx);
        f_v.min(f_l)
    };
    let fresnel = match eta.known() {
        Some(e) if e >= 1.0 => microfacet(),
        Some(_) => macro_surface(),
        None => F::select(eta.lt_lit(1.0), macro_surface(), microfacet()),
    }
    .named(&name("fresnel"));
    f_cook_torrance(distribution, shadowing, fresnel.splat(), g.n_dot_v, g.n_dot_l)
}

/// A coat's dielectric Fresnel reflectance at cosine `cos_i` from above: exact, or Schlick's
/// approximation when asked for ([`Approximations::schlick_fresnel`]). Schlick's needs the
/// cosine on the optically thinner side, which for η < 1 is the refracted one, with total
/// internal reflection where it does not exist (`fr_dielectric_schlick`); a literal η ≥ 1
/// skips that.
fn dielectric_fresnel<F: Real>(cos_i: F, eta: F, approx: Approximations) -> F {
    if !approx.schlick_fresnel {
        return fr_dielectric(cos_i, eta);
    }
    match eta.known() {
        Some(e) if e >= 1.0 => f_schlick_scalar(f0_dielectric(eta), cos_i.clamp(0.0, 1.0)),
        _ => fr_dielectric_schlick(cos_i, eta),
    }
}

/// The base's own BRDF at the directions of its level. `n_medium` is the absolute IOR of the
/// medium the base sits in (`None`: air), which changes a conductor's Fresnel reflectance;
/// `blur` widens a conductor's lobe (see [`interfaced`]).
fn base_brdf<F: Real>(
    body: &Body<'_>,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    n_medium: Option<F>,
    blur: Option<F>,
) -> F::Vec {
    let f = unguarded_base_brdf(body, inputs, g, n_medium, blur);
    match g.shading_cosine_ratio() {
        Some(ratio) => {
            let above = g.raw_n_dot_v.gt_lit(0.0);
            F::Vec::select(above, f * ratio, inputs.zero())
        }
        None => f,
    }
}

fn unguarded_base_brdf<F: Real>(
    body: &Body<'_>,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    n_medium: Option<F>,
    blur: Option<F>,
) -> F::Vec {
    match body {
        Body::Lambert(albedo) => fd_lambert::<F>(inputs.color(*albedo)),
        Body::OrenNayar(albedo, sigma) => {
            fd_oren_nayar(inputs.color(*albedo), inputs.scalar(*sigma), g.n_dot_v, g.n_dot_l, g.v_dot_l())
        }
        Body::Eon(albedo, r) => fd_eon(inputs.color(*albedo), inputs.scalar(*r), g.n_dot_v, g.n_dot_l, g.v_dot_l()),
        Body::Conductor(roughness, fresnel) => {
            let alpha = conductor_alpha(inputs.scalar(*roughness), blur, g.level);
            let name = |base| level_name(base, g.level);
            let half = g.half();
            let distribution = d_ggx(half.n_dot_h, half.sin2_h, alpha).named(&name("d"));
            let shadowing = g_smith_ggx_correlated(g.n_dot_v, g.n_dot_l, alpha).named(&name("g"));
            let f = conductor_fresnel(fresnel, inputs, half.v_dot_h, n_medium).named(&name("fresnel"));
            f_cook_torrance(distribution, shadowing, f, g.n_dot_v, g.n_dot_l)
        }
    }
}

/// A conductor's GGX α = r², widened to α + blur under rough coats.
fn conductor_alpha<F: Real>(roughness: F, blur: Option<F>, level: usize) -> F {
    let alpha = roughness * roughness;
    match blur {
        Some(b) => (alpha + b).named(&level_name("alpha", level)),
        None => alpha,
    }
}

/// The body's directional albedos towards l and v and its mean albedo, for the coat above.
fn body_albedo<F: Real>(
    body: &Body<'_>,
    inputs: &Inputs<F>,
    g: &Geometry<F>,
    n_medium: Option<F>,
    blur: Option<F>,
) -> Albedo<F> {
    let name = |base| level_name(base, g.level);
    let mean = base_mean_albedo(body, inputs, g.level, n_medium, blur).named(&name("rho"));
    let (e_l, e_v) = match body {
        // Lambert's albedo is the same in every direction; the qualitative Oren–Nayar lobe's
        // directional albedo is approximated by its mean.
        Body::Lambert(_) | Body::OrenNayar(..) => (mean, mean),
        Body::Eon(albedo, r) => {
            let (albedo, r) = (inputs.color(*albedo), inputs.scalar(*r));
            (albedo_eon(albedo, r, g.n_dot_l), albedo_eon(albedo, r, g.n_dot_v))
        }
        // E(μ) ≈ E_GGX(μ; α) F(μ): the white lobe's albedo times Fresnel at the mirror direction.
        Body::Conductor(roughness, fresnel) => {
            let r = conductor_alpha(inputs.scalar(*roughness), blur, g.level).sqrt();
            let at = |mu: F| {
                let white = tables::lookup(TableId::GgxAlbedo, &[mu, r]);
                conductor_fresnel(fresnel, inputs, mu, n_medium) * white
            };
            (at(g.n_dot_l), at(g.n_dot_v))
        }
    };
    // The light's first hit on a normal-mapped body scales with its own cosine (see
    // `Geometry::shading_cosine_ratio`), and so does all that follows from it.
    let e_l = match g.shading_cosine_ratio() {
        Some(ratio) => e_l * ratio,
        None => e_l,
    };
    Albedo { e_l: e_l.named(&name("albedo_l")), e_v: e_v.named(&name("albedo_v")), mean }
}

fn conductor_fresnel<F: Real>(fresnel: &ConductorFresnel, inputs: &Inputs<F>, cos: F, n_medium: Option<F>) -> F::Vec {
    match fresnel {
        ConductorFresnel::F0(f0) => {
            let f0 = inputs.color(*f0);
            let f0 = n_medium.map_or(f0, |n| f0_under_medium(f0, n).named("f0_under_coat"));
            f_schlick(f0, cos)
        }
        ConductorFresnel::Complex { eta, k } => {
            let (eta, k) = (inputs.color(*eta), inputs.color(*k));
            let (eta, k) = match n_medium {
                Some(n) => (eta / n, k / n),
                None => (eta, k),
            };
            fr_conductor(cos, eta, k)
        }
    }
}

/// The hemispherical-average albedo of the base (for the interfaced method's inter-reflections).
fn base_mean_albedo<F: Real>(
    body: &Body<'_>,
    inputs: &Inputs<F>,
    level: usize,
    n_medium: Option<F>,
    blur: Option<F>,
) -> F::Vec {
    match body {
        Body::Lambert(albedo) => inputs.color(*albedo),
        Body::OrenNayar(albedo, sigma) => albedo_avg_oren_nayar(inputs.color(*albedo), inputs.scalar(*sigma)),
        Body::Eon(albedo, r) => albedo_avg_eon(inputs.color(*albedo), inputs.scalar(*r)),
        Body::Conductor(roughness, fresnel) => {
            let f0 = conductor_fresnel(fresnel, inputs, inputs.lit(1.0), n_medium);
            let r = conductor_alpha(inputs.scalar(*roughness), blur, level).sqrt();
            let white = tables::lookup(TableId::GgxAlbedoAvg, &[r]);
            albedo_avg_conductor::<F>(f0) * white
        }
    }
}

/// The cosine μc = √(1 − 1/η²) of a coat's escape cone seen from inside (0 without TIR, η ≤ 1).
fn escape_cone_cosine<F: Real>(eta: F) -> F {
    eta.sq().recip().one_minus().at_least(0.0).sqrt()
}

/// The return factor of a first pass (see [`FirstPass`]): the share 1 − ξ of the first
/// reflection that does not escape, against the clear slab's R(0), clamped to [0, 1] (never more
/// than a diffusing body returns). Guard: R(0) ≥ 10⁻⁴.
fn first_return<F: Real>(escaped: F::Vec, r_clear: F, inputs: &Inputs<F>) -> F::Vec {
    let one = inputs.lit(1.0).splat();
    ((one - escaped) / r_clear.at_least(1e-4)).max(inputs.zero()).min(one)
}

/// Which slab integral [`slab_integral`] computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlabIntegral {
    /// R(τ) = ∫₀¹ 2μ e^{−2τ/μ} F_int(μ) dμ.
    Return,
    /// E_esc(τ) = ∫₀¹ 2μ e^{−τ/μ} (1 − F_int(μ)) dμ.
    Escape,
}

/// The hemispherical integrals of a coat's slab seen from inside (research/accuracy.md §1.4),
/// by Gauss–Legendre quadrature in two pieces (one node per call of [`slab_tir_node`],
/// [`slab_return_node`] or [`slab_escape_node`]), each with a substitution that makes its
/// integrand smooth:
///
/// * the TIR cone μ ∈ [0, μc] (μc = √(1 − 1/η²), where F_int = 1), with μ = μc t²: it clusters
///   nodes near μ = 0, where e^{−2τ/μ} rises steeply for small τ;
/// * μ ∈ [μc, 1] with μ = μc + (1 − μc) s²: Fresnel behaves like √(μ − μc) at the critical
///   angle, which is linear in s.
///
/// 12 + 12 nodes give an absolute error below 10⁻⁶ for η ∈ (1, 3] and all τ ≥ 0 (measured
/// against adaptive quadrature in the tests). For η ≤ 1 there is no TIR cone (μc = 0).
pub fn slab_integral<F: Real>(eta: F, tau: F::Vec, which: SlabIntegral) -> F::Vec {
    let mu_c = escape_cone_cosine(eta).named("mu_c");
    let inv_eta = eta.recip().named("inv_eta");
    let mut sum = eta.lit(0.0).splat();
    if which == SlabIntegral::Return {
        for (t, w) in GAUSS_LEGENDRE_12 {
            sum = sum + slab_tir_node(mu_c, tau, mu_c.lit(t as f32), mu_c.lit(w as f32)).named("node");
        }
    }
    for (s, w) in GAUSS_LEGENDRE_12 {
        let (s, w) = (mu_c.lit(s as f32), mu_c.lit(w as f32));
        let node = match which {
            SlabIntegral::Return => slab_return_node(mu_c, inv_eta, tau, s, w),
            SlabIntegral::Escape => slab_escape_node(mu_c, inv_eta, tau, s, w),
        };
        sum = sum + node.named("node");
    }
    sum
}

/// The smooth rest ∫ (p − h) du of `trapped_escape` over the cone, u = μc² + d, d ∈ [0, 1 − μc²]:
/// the trapped share p (`trapped_share`) minus its edge profile h(d) = ½(1 − d/√(w² + d²)),
/// by 4-point Gauss–Legendre quadrature.
pub fn trapped_rest<F: Real>(mu_c: F, alpha: F, w: F) -> F {
    let c2 = mu_c.sq();
    let width = c2.one_minus();
    let mut sum = mu_c.lit(0.0);
    for (x, weight) in GAUSS_LEGENDRE_4 {
        let d = width * x;
        let p = trapped_share((c2 + d).sqrt(), mu_c, alpha);
        let h = (d / (w.sq() + d.sq()).sqrt()).one_minus() * 0.5;
        sum = sum + (p - h).named("node") * weight;
    }
    sum * width
}

/// Q of `eon_escape_shape`: the integral over the escape cone of a smooth interface of
/// relative IOR `eta`, with the nodes of [`slab_integral`] (no TIR part: nothing escapes there).
pub fn eon_escape_q<F: Real>(eta: F) -> F {
    let mu_c = escape_cone_cosine(eta).named("mu_c");
    let inv_eta = eta.recip().named("inv_eta");
    let mut q = eta.lit(0.0);
    for (s, w) in GAUSS_LEGENDRE_12 {
        q = q + eon_escape_node(mu_c, inv_eta, mu_c.lit(s as f32), mu_c.lit(w as f32)).named("node");
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::quadrature::reference::adaptive_simpson;
    use glam::Vec3;

    fn fresnel_inside(mu: f64, eta: f64) -> f64 {
        let e = 1.0 / eta;
        let sin2_t = (1.0 - mu * mu) / (e * e);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        let ct = (1.0 - sin2_t).sqrt();
        let rs = (mu - e * ct) / (mu + e * ct);
        let rp = (e * mu - ct) / (e * mu + ct);
        0.5 * (rs * rs + rp * rp)
    }

    /// Largest absolute quadrature error tolerated for the slab integrals.
    const SLAB_ABS_TOLERANCE: f64 = 2e-6;

    #[test]
    fn slab_integrals_match_adaptive_quadrature() {
        for eta in [0.8_f64, 1.2, 1.33, 1.5, 2.0, 3.0] {
            for tau in [0.0_f64, 1e-3, 0.01, 0.05, 0.25, 1.0, 4.0] {
                let mu_c = (1.0 - 1.0 / (eta * eta)).max(0.0).sqrt();
                let ret = |mu: f64| 2.0 * mu * (-2.0 * tau / mu.max(1e-300)).exp() * fresnel_inside(mu, eta);
                let esc = |mu: f64| 2.0 * mu * (-tau / mu.max(1e-300)).exp() * (1.0 - fresnel_inside(mu, eta));
                let r_ref = adaptive_simpson(&ret, 0.0, mu_c, 1e-12, 40) + adaptive_simpson(&ret, mu_c, 1.0, 1e-12, 40);
                let e_ref = adaptive_simpson(&esc, mu_c, 1.0, 1e-12, 40);
                let r = slab_integral(eta as f32, Vec3::splat(tau as f32), SlabIntegral::Return).x as f64;
                let e = slab_integral(eta as f32, Vec3::splat(tau as f32), SlabIntegral::Escape).x as f64;
                assert!((r - r_ref).abs() < SLAB_ABS_TOLERANCE, "R eta {eta} tau {tau}: {r} vs {r_ref}");
                assert!((e - e_ref).abs() < SLAB_ABS_TOLERANCE, "E eta {eta} tau {tau}: {e} vs {e_ref}");
            }
        }
    }

    #[test]
    fn clear_slab_identity() {
        // 1 − E_F = η²(1 − K): with τ = 0, η² E_esc + (1 − η² E_esc) = 1 and K = 1 − E_esc.
        let e = slab_integral(1.5_f32, Vec3::ZERO, SlabIntegral::Escape).x;
        let r = slab_integral(1.5_f32, Vec3::ZERO, SlabIntegral::Return).x;
        assert!((e + r - 1.0).abs() < 1e-6, "E_esc + K = {}", e + r);
        // K(1.5) = 0.59635 (research/accuracy.md §6.2).
        assert!((r - 0.596_35).abs() < 1e-4, "K = {r}");
    }
}
