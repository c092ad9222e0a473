//! Microfacet terms: normal distributions (GGX, GTR1), masking–shadowing (Smith, Schlick-GGX),
//! Fresnel (dielectric, conductor, Schlick), the Cook–Torrance lobe, the half vector and
//! refraction.

use std::f32::consts::PI;

use crate::math::Vector;
use crate::math::shading_fn;

/// Smallest GGX / GTR1 α. Below it a microfacet lobe is a mirror for all practical purposes
/// (pbrt-v4's `EffectivelySmooth` threshold); clamping keeps D finite at n·h = 1, where its peak
/// value 1/(πα²) ≈ 3.2·10⁵ is still representable in f32.
pub const ALPHA_MIN: f32 = 1e-3;

/// Roughness above which GTR1's α²−1 → 0 and ln α² → 0 cancel badly; the limit there is D = 1/π.
const GTR1_ALPHA_MAX: f32 = 0.9999;

/// Largest Schlick F0 accepted when converting F0 back to an IOR (η = (1+√F0)/(1−√F0) → ∞ at 1).
const F0_MAX: f32 = 0.9999;

/// Smallest argument of a square root or reciprocal that would otherwise hit 0 at grazing angles.
pub(super) const TINY: f32 = 1e-12;

/// The roughness α_g of the Disney clear-coat's Smith term: fixed at 0.25 (Burley 2012;
/// Bowsher 2022, §3.0.2).
pub const GTR1_SMITH_ROUGHNESS: f32 = 0.25;

shading_fn! {
    /// Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 33
    /// (Bowsher 2022, eq. 6): the GGX / Trowbridge–Reitz distribution D(h) = α² / (π (α² cos²θh +
    /// sin²θh)²), sin²θh = |n × h|² passed in. Guards: α ≥ ALPHA_MIN = 10⁻³ keeps the peak finite; the
    /// denominator ≥ TINY for a zero half vector (two zero directions under total internal reflection).
    ///
    /// The usual denominator ((n·h)²(α² − 1) + 1)² is written with sin²θh passed in (Filament's
    /// `D_GGX` does the same): 1 − (n·h)² cancels catastrophically in f32 at the peak of a sharp lobe.
    /// For a unit h the denominator is never below α² ≥ 10⁻⁶.
    pub fn d_ggx(cos_h: S, sin2_h: S, alpha: S) -> S {
        let a = alpha.at_least(ALPHA_MIN);
        let a_sq = a * a;
        let denom = (cos_h * cos_h * a_sq + sin2_h).at_least(TINY);
        a_sq / (denom * denom * PI)
    }
}

/// Smallest refracted cosine by which [`d_ggx_crossed`]'s callers divide a crossing's blur
/// (β = σ²/μ′²): a direction refracted almost flat (a coat of IOR just above 1 seen near
/// grazing) would otherwise spread the lobe without bound across its plane.
pub const CROSSED_COSINE_MIN: f32 = 0.05;

shading_fn! {
    /// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs", §5.3–5.4:
    /// GGX with the slope covariance A = α² I + Σ_l + Σ_v, each coat crossing spreading the slopes by
    /// σ² along its direction's plane of incidence and β = σ²/μ² across it;
    /// D = 1 / (π √det A · cos⁴θh · (1 + sᵀA⁻¹s)²). Guards: det ≥ TINY (α ≥ ALPHA_MIN makes it
    /// ≥ 10⁻¹²); the bracket cos²θh + … ≥ TINY for a zero half vector, as in `d_ggx`.
    ///
    /// An anisotropic distribution is the isotropic one linearly stretched in slope space. An angular
    /// spread δ moves a direction's horizontal part by μδ in its plane, by δ across it:
    /// Σ = β I − β x_t x_tᵀ, x_t the direction's horizontal part (|x_t|² = 1 − μ²), and s = h_t/cos θh
    /// the half vector's slope. Written without a tangent frame: with c = α² + β_l + β_v and
    /// m = α² + β_l μ_l² + β_v μ_v² (A's trace is c + m), det A = c·m + β_l β_v t², t = n·(l × v),
    /// and cos²θh · sᵀ adj(A) s = m sin²θh + β_l (l·h − μ_l cos θh)² + β_v (l·h − μ_v cos θh)²
    /// (x_t·h = x·h − μ cos θh; v·h = l·h). Every term is ≥ 0, and at β_l = β_v = 0 it is [`d_ggx`].
    /// `base` is α², `twist_sq` t².
    pub fn d_ggx_crossed(cos_h: S, sin2_h: S, l_dot_h: S, mu_l: S, mu_v: S, twist_sq: S, base: S, beta_l: S, beta_v: S) -> S {
        let base = base.at_least(ALPHA_MIN * ALPHA_MIN);
        let across = base + beta_l + beta_v;
        let along = base + beta_l * mu_l * mu_l + beta_v * mu_v * mu_v;
        let det = (across * along + beta_l * beta_v * twist_sq).at_least(TINY);
        let off_l = l_dot_h - mu_l * cos_h;
        let off_v = l_dot_h - mu_v * cos_h;
        let spread = along * sin2_h + beta_l * off_l * off_l + beta_v * off_v * off_v;
        let bracket = (cos_h * cos_h + spread / det).at_least(TINY);
        (det.sqrt() * bracket * bracket * PI).recip()
    }
}

shading_fn! {
    /// Burley 2012, "Physically-Based Shading at Disney", App. B, GTR with γ = 1 (Bowsher 2022,
    /// eq. 10): D = (α² − 1) / (π ln α² (α² cos²θh + sin²θh)). Guards: α ≥ ALPHA_MIN = 10⁻³ (ln 0);
    /// at α → 1 the 0/0 limit 1/π is taken directly; the bracket ≥ TINY for a zero half vector, as
    /// in `d_ggx`.
    ///
    /// Burley writes the bracket 1 + (α² − 1) cos²θh; it is written as in `d_ggx`.
    pub fn d_gtr1(cos_h: S, sin2_h: S, alpha: S) -> S {
        let a = alpha.clamp(ALPHA_MIN, GTR1_ALPHA_MAX);
        let a_sq = a * a;
        let d = (a_sq - 1.0) / (a_sq.ln() * (cos_h * cos_h * a_sq + sin2_h).at_least(TINY) * PI);
        F::select(alpha.gt_lit(GTR1_ALPHA_MAX), alpha.lit(1.0 / PI), d)
    }
}

shading_fn! {
    /// Schlick 1994 as used by Karis 2013, "Real Shading in Unreal Engine 4"
    /// (Bowsher 2022, eq. 7): the Schlick-GGX masking term G1 = n·x / ((n·x)(1 − k) + k).
    pub fn g1_schlick_ggx(n_dot_x: S, k: S) -> S {
        n_dot_x / (n_dot_x * k.one_minus() + k)
    }
}

shading_fn! {
    /// Karis 2013 with Burley's remapping (Bowsher 2022, eq. 8–9): Smith's separable product of
    /// two Schlick-GGX terms with k = (roughness + 1)² / 8.
    pub fn g_smith_schlick_ggx(n_dot_v: S, n_dot_l: S, roughness: S) -> S {
        let k = (roughness + 1.0).sq() / 8.0;
        g1_schlick_ggx(n_dot_v, k) * g1_schlick_ggx(n_dot_l, k)
    }
}

shading_fn! {
    /// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
    /// eq. 72: the GGX Smith auxiliary function Λ(μ) = (√(1 + α² tan²θ) − 1) / 2.
    /// Guard: μ² ≥ TINY (the caller clamps μ; this keeps the division defined at μ = 0).
    pub fn lambda_ggx(n_dot_x: S, alpha: S) -> S {
        let mu_sq = (n_dot_x * n_dot_x).at_least(TINY);
        let tan_sq = mu_sq.one_minus() / mu_sq;
        ((alpha * alpha * tan_sq + 1.0).sqrt() - 1.0) * 0.5
    }
}

shading_fn! {
    /// Heitz 2014, eq. 99: the exact height-correlated Smith masking-shadowing for GGX,
    /// G2 = 1 / (1 + Λ(v) + Λ(l)).
    pub fn g_smith_ggx_correlated(n_dot_v: S, n_dot_l: S, alpha: S) -> S {
        let alpha = alpha.at_least(ALPHA_MIN);
        (lambda_ggx(n_dot_v, alpha).named("lambda_v") + lambda_ggx(n_dot_l, alpha).named("lambda_l") + 1.0).recip()
    }
}

shading_fn! {
    /// Smith's auxiliary function for Burley's GTR1 distribution (`d_gtr1`), from its slopes (Heitz
    /// 2014, eq. 72; docs/derivations.md, "Smith masking of GTR1"): with c = n·x,
    /// Λ = [(1 + c)·x + c·ln(1 − x)] / (−c ln α²), x = (1 − c)(1 − α²) / (1 + √(c² + α²(1 − c²))).
    /// Guards: α clamped to [ALPHA_MIN, GTR1_ALPHA_MAX] as in `d_gtr1`, whose limit at α → 1 (the
    /// uniform D = 1/π) has Λ = (1 − c)/(2c); c ≥ 10⁻⁶ (keeps the division defined at c = 0).
    ///
    /// Λ(μ) = (1/m)∫_m^∞ (q − m) P2(q) dq with m = cot θ, and GTR1's marginal slope density is
    /// P2(q) = (1/√(q² + α²) − 1/√(q² + 1))/(−ln α²). The form above has no cancellation towards the
    /// pole (x → 0 there: Λ ≈ x/(−ln α²)). Burley pairs GTR1 with GGX's Smith term at α = 0.25
    /// (`GTR1_SMITH_ROUGHNESS`), which belongs to no microsurface; the interfaced method's coat is a
    /// GTR1 microsurface, which needs its own.
    pub fn lambda_gtr1(n_dot_x: S, alpha: S) -> S {
        let a = alpha.clamp(ALPHA_MIN, GTR1_ALPHA_MAX);
        let a_sq = a * a;
        let c = n_dot_x.clamp(1e-6, 1.0);
        let root = (c * c + a_sq * (c * c).one_minus()).sqrt();
        let x = c.one_minus() * a_sq.one_minus() / (root + 1.0);
        let lambda = ((c + 1.0) * x + c * x.one_minus().ln()) / (c * a_sq.recip().ln());
        F::select(alpha.gt_lit(GTR1_ALPHA_MAX), c.one_minus() / (c * 2.0), lambda)
    }
}

shading_fn! {
    /// Heitz 2014, eq. 99, for GTR1's Λ (`lambda_gtr1`): the height-correlated Smith
    /// masking-shadowing G2 = 1 / (1 + Λ(v) + Λ(l)) of a GTR1 microsurface.
    pub fn g_smith_gtr1_correlated(n_dot_v: S, n_dot_l: S, alpha: S) -> S {
        (lambda_gtr1(n_dot_v, alpha) + lambda_gtr1(n_dot_l, alpha) + 1.0).recip()
    }
}

shading_fn! {
    /// Cook & Torrance 1982 (Bowsher 2022, eq. 4): the microfacet reflection
    /// f = D G F / (4 (n·l)(n·v)). The caller passes cosines clamped to ≥ COS_EPSILON.
    pub fn f_cook_torrance(d: S, g: S, fresnel: V, n_dot_v: S, n_dot_l: S) -> V {
        fresnel * (d * g / (n_dot_v * n_dot_l * 4.0))
    }
}

/// The walks' second event per the share `second_event_share` gives for a direction well above
/// the microsurface's slopes (Λ ≤ 0.02): the third and later events add about a tenth (1.03–1.25
/// over the probed pairs, `glazec-lab` example `second_event`). In f64 for the tables' own
/// copy of the lobe (`glazec_lab::bake::coat_lobe`); the shader's is the same value in f32.
pub const SECOND_EVENT_LATER: f64 = 1.1;

shading_fn! {
    /// The tail of the GGX distribution (Walter et al. 2007, eq. 33) at the half vector of l and v
    /// with the lower one mirrored in the mean plane (a rough coat's second microfacet event):
    /// D = α² H² / (π (α² z² + across)²), H = z² + across, times tan²θh/(tan²θh + α²), with
    /// across = |n × (l + v)|², z = n·l − n·v. Guards: α ≥ ALPHA_MIN; the bracket ≥ TINY; the tail is
    /// 0 for a pair that mirror into each other (H = 0), as it is for rounding near there.
    ///
    /// `CoatInterface::second_event` uses it. The half vector has the horizontal part of l + v and
    /// the vertical part z, so tan²θh = across/z². The factor keeps the tail (θh ≫ α, facets steeper
    /// than the first reflection's spread) and takes the peak away: near a grazing mirror direction
    /// the walks' second event is 0.06 of the single-scattering lobe for α 0.25 (80°/78°), where D
    /// alone gave 0.16 and the tail 0.06. H = 0 where l and v are at one elevation on opposite sides,
    /// or both normal; rounding near there gives H ~ 10⁻¹⁴.
    pub fn d_ggx_mirrored_tail(z: S, across: S, alpha: S) -> S {
        let a = alpha.at_least(ALPHA_MIN);
        let a_sq = a * a;
        let h_sq = z * z + across;
        let denom = (z * z * a_sq + across).at_least(TINY);
        a_sq * h_sq * h_sq * across / (denom * denom * denom * PI)
    }
}

shading_fn! {
    /// How much light arriving at a GGX microsurface from a direction of Smith Λ (`lambda`) comes back
    /// through a second event after a reflection near the mirror direction, per the first event's
    /// Fresnel factor and the lobe at the mirrored half vector: 1.1/(1 + 4Λ + 2Λ²), fitted to Heitz
    /// et al. 2016 microsurface walks.
    ///
    /// `CoatInterface::second_event` uses it; the fit is the `glazec-lab` example `second_event`. For
    /// α ≪ the direction's elevation the chance of a second event, ≈ Λ, and the visible-normal
    /// density there, over a projected area ≈ Λ·μ, cancel to 1 (the 1.1 is the later events,
    /// [`SECOND_EVENT_LATER`]); as α grows past the elevation the reflected rays spread and the
    /// share falls: the walks give 0.87 at Λ = 0.08, 0.47 at 0.26, 0.21 at 0.75, 0.07 at 2.1,
    /// independent of η.
    pub fn second_event_share(lambda: S) -> S {
        (lambda * (lambda * 2.0 + 4.0) + 1.0).recip() * SECOND_EVENT_LATER as f32
    }
}

shading_fn! {
    /// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering"
    /// (Bowsher 2022, eq. 5): F(θ) = F0 + (1 − F0)(1 − cos θ)⁵.
    pub fn f_schlick(f0: V, cos_theta: S) -> V {
        let m = cos_theta.clamp(0.0, 1.0).one_minus();
        let m_sq = m * m;
        f0 + f0.one_minus() * (m_sq * m_sq * m)
    }
}

shading_fn! {
    /// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", eq. 15, for one
    /// scalar reflectance (a dielectric's): F = F0 + (1 − F0)(1 − cos θ)⁵.
    pub fn f_schlick_scalar(f0: S, cos_theta: S) -> S {
        let m = cos_theta.one_minus();
        let m_sq = m * m;
        f0 + f0.one_minus() * (m_sq * m_sq * m)
    }
}

shading_fn! {
    /// Schlick 1994 eq. 15 for a dielectric interface of relative IOR η from either side: the
    /// cosine in the power term must be the one in the optically thinner medium, so for η < 1
    /// it is the refracted cosine √(1 − (1 − cos²θ)/η²), and beyond the critical angle the
    /// reflectance is 1 (total internal reflection; the rejected branch is then NaN).
    pub fn fr_dielectric_schlick(cos_i: S, eta: S) -> S {
        let cos_i = cos_i.clamp(0.0, 1.0);
        let sin2_t = cos_i.sq().one_minus() / (eta * eta);
        let cos_t = sin2_t.one_minus().at_least(0.0).sqrt();
        let cos_thin = F::select(eta.lt_lit(1.0), cos_t, cos_i);
        let f0 = ((eta - 1.0) / (eta + 1.0)).sq();
        let m = cos_thin.one_minus();
        let m_sq = m * m;
        let schlick = f0 + f0.one_minus() * (m_sq * m_sq * m);
        F::select(sin2_t.lt_lit(1.0), schlick, cos_i.lit(1.0))
    }
}

shading_fn! {
    /// The normal-incidence reflectance of a dielectric interface, F0 = ((η − 1)/(η + 1))².
    pub fn f0_dielectric(eta: S) -> S {
        ((eta - 1.0) / (eta + 1.0)).sq()
    }
}

shading_fn! {
    /// Fresnel equations for an unpolarised dielectric interface (Born & Wolf 1999; pbrt-v4
    /// `FrDielectric`). `cos_i` ≥ 0 on the incident side; `eta` = n_transmitted / n_incident.
    /// Total internal reflection (sin²θt ≥ 1) returns 1; the other branch is then NaN and
    /// rejected by the select.
    pub fn fr_dielectric(cos_i: S, eta: S) -> S {
        let cos_i = cos_i.clamp(0.0, 1.0);
        let sin2_t = cos_i.sq().one_minus() / (eta * eta);
        let cos_t = sin2_t.one_minus().at_least(0.0).sqrt();
        let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
        let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
        let fresnel = (r_parl * r_parl + r_perp * r_perp) * 0.5;
        F::select(sin2_t.lt_lit(1.0), fresnel, cos_i.lit(1.0))
    }
}

shading_fn! {
    /// Fresnel reflectance of a conductor with complex IOR η + iκ, unpolarised, per channel
    /// (Born & Wolf 1999; the closed form of pbrt-v3 `FrConductor`). `eta`, `k` are relative to
    /// the medium above.
    pub fn fr_conductor(cos_i: S, eta: V, k: V) -> V {
        let cos2 = cos_i.clamp(0.0, 1.0).sq();
        let sin2 = cos2.one_minus();
        let eta2 = eta * eta;
        let k2 = k * k;
        let t0 = eta2 - k2 - sin2.splat();
        let a2_plus_b2 = (t0 * t0 + eta2 * k2 * 4.0).sqrt();
        let t1 = a2_plus_b2 + cos2.splat();
        let a = ((a2_plus_b2 + t0) * 0.5).sqrt();
        let t2 = a * (cos2.sqrt() * 2.0);
        let r_s = (t1 - t2) / (t1 + t2);
        let t3 = a2_plus_b2 * cos2 + (sin2 * sin2).splat();
        let t4 = t2 * sin2;
        let r_p = r_s * (t3 - t4) / (t3 + t4);
        (r_p + r_s) * 0.5
    }
}

shading_fn! {
    /// Re-expresses a conductor's F0 (given against air) for a base that sits in a medium of
    /// absolute index `n_medium`: F0 → η = (1+√F0)/(1−√F0) → η/n → F0′ (the approach of
    /// Filament's `f0ClearCoatToSurface`, generalised from n = 1.5). Guard: F0 ≤ F0_MAX.
    pub fn f0_under_medium(f0: V, n_medium: S) -> V {
        let s = f0.min(n_medium.lit(F0_MAX).splat()).sqrt();
        let eta = (s + n_medium.lit(1.0).splat()) / s.one_minus() / n_medium;
        let r = (eta - n_medium.lit(1.0).splat()) / (eta + n_medium.lit(1.0).splat());
        r * r
    }
}

shading_fn! {
    /// Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks": the hemispherical
    /// average of Schlick's Fresnel, F_avg = F0 + (1 − F0)/21. Used as a conductor's mean albedo
    /// (an approximation that ignores the lobe's single-scattering loss).
    pub fn albedo_avg_conductor(f0: V) -> V {
        f0 + f0.one_minus() * (1.0 / 21.0)
    }
}

shading_fn! {
    /// Snell's law at a horizontal interface: the direction `w` (pointing away from the surface,
    /// above it) continued into a layer of relative IOR `eta` below, again pointing up and away:
    /// −refract(−w, n, 1/η). On total internal reflection (only possible for η < 1) it is the
    /// zero vector, whose cosine 0 makes every transmission factor 0.
    pub fn refract_down(w: V, n: V, eta: S) -> V {
        -((-w).refract(n, eta.recip()))
    }
}

shading_fn! {
    /// The microfacet half vector h = (v + l)/|v + l| (Torrance & Sparrow 1967).
    /// Guard: |v + l|² ≥ TINY. Under total internal reflection a refracted direction is the zero
    /// vector, and both can be; h is then 0 rather than NaN (its lobe is multiplied by zero
    /// transmission anyway).
    pub fn half_vector(v: V, l: V) -> V {
        let sum = v + l;
        sum / sum.dot(sum).at_least(TINY).sqrt()
    }
}

shading_fn! {
    /// The roughness at which an isotropic prefiltered environment is looked up for the reflection of
    /// a GGX interface of roughness r seen at n·v = μ: r√μ, a lobe of GGX α μ (Walter et al. 2007,
    /// eq. 14). Guard: μ ≥ 10⁻⁴ (a view below the horizon has no weight).
    ///
    /// Reflection maps a half vector's deviation δ from the normal to 2δ in the plane of incidence but
    /// to 2(h·v)δ across it (the reflected direction covers 4(h·v) times the half vector's solid
    /// angle), so as the view grazes the lobe narrows across that plane by μ while the prefiltered
    /// levels assume μ = 1 (Karis 2013's n = v = r). One isotropic lookup must choose one width; the
    /// narrower keeps what the reflection really resolves across the plane of incidence, such as a
    /// horizon seen at a grazing view, and under-blurs along it.
    pub fn grazing_lookup_roughness(r: S, n_dot_v: S) -> S {
        r * n_dot_v.at_least(1e-4).sqrt()
    }
}

shading_fn! {
    /// Lagarde & de Rousiers 2014, "Moving Frostbite to Physically Based Rendering", listing 22:
    /// the direction a GGX lobe of roughness α around the mirror direction r = 2(n·v)n − v
    /// reflects most light from, pulled towards n as α grows: normalize(mix(n, r, s(√s + α))),
    /// s = 1 − α. Guards: n·v ≥ 0 (a view below the horizon reflects nothing; its weight is zero)
    /// and |mix| ≥ TINY.
    pub fn specular_dominant_direction(n: V, v: V, alpha: S) -> V {
        let r = n * (n.dot(v).at_least(0.0) * 2.0) - v;
        let smoothness = alpha.one_minus().clamp(0.0, 1.0);
        let t = smoothness * (smoothness.sqrt() + alpha);
        let d = n * t.one_minus() + r * t;
        d / d.dot(d).at_least(TINY).sqrt()
    }
}
