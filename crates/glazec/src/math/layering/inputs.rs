//! What a layering method reads: runtime-parameter values and literal constants ([`Inputs`]),
//! and the stack expanded into coats over an opaque body ([`Body`]).

use super::level::Blur;
use crate::math::{Real, Slot, Vector};
use crate::model::{Approximations, Base, Coat, Color, ConductorFresnel, Lobe, Material, Scalar};

/// Runtime-parameter values and literal constants, as values of the [`Real`] family.
pub struct Inputs<F: Real> {
    pub(super) ctx: F::Ctx,
    pub(super) params: Vec<Slot<F>>,
    /// Per-layer shading normals (coats, then the base), for layers with a normal map.
    pub(super) normals: Vec<(usize, F::Vec)>,
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

    pub(super) fn layer_normal(&self, layer: usize) -> Option<F::Vec> {
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

    /// A coat's slab's optical depth τ = absorption × thickness (per channel).
    pub(super) fn optical_depth(&self, coat: &Coat) -> F::Vec {
        self.color(coat.absorption) * self.scalar(coat.thickness)
    }

    pub(super) fn zero(&self) -> F::Vec {
        self.lit(0.0).splat()
    }
}

/// The stack a layering method walks, and how: the same for every level of the walk.
pub(super) struct Stack<'s, F: Real> {
    /// The coats, top first, after [`expand`].
    pub(super) coats: &'s [Coat],
    pub(super) body: &'s Body<'s>,
    pub(super) inputs: &'s Inputs<F>,
    /// The interfaced method's approximations (ignored by the seed's methods).
    pub(super) approx: Approximations,
}

/// Where a walk down the stack is: at coat `k` (the body when `k` is the number of coats), in a
/// medium of absolute IOR `n_medium` (`None`: air), under coats whose roughness widens the lobes
/// below by `blur` (see `level::BLUR_WIDTH`) and spread the light's Snell invariant by
/// `spread` (`CoatInterface::p_spread`; `None` under smooth coats only).
#[derive(Clone, Copy)]
pub(super) struct Depth<F: Real> {
    pub(super) k: usize,
    pub(super) n_medium: Option<F>,
    pub(super) blur: Blur<F>,
    pub(super) spread: Option<F>,
    /// The cosines (towards l and v) along which the light of the coat directly above meets an
    /// Oren–Nayar body, whose directional albedo follows them: the coat's path cosines
    /// (`CoatInterface::path_cosine`), as for EON's first pass; `None` elsewhere.
    pub(super) incidence: Option<(F, F)>,
}

impl<F: Real> Depth<F> {
    /// The top of the stack, in air.
    pub(super) fn top() -> Self {
        Depth { k: 0, n_medium: None, blur: Blur::none(), spread: None, incidence: None }
    }
}

/// The opaque body of a stack after expansion (a `Plastic` base is a GGX coat over Lambert).
pub(super) enum Body<'m> {
    Lambert(Color),
    OrenNayar(Color, Scalar),
    Eon(Color, Scalar),
    Conductor(Scalar, &'m ConductorFresnel),
}

pub(super) fn expand(material: &Material) -> (Vec<Coat>, Body<'_>) {
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
