//! Normal maps: decoding a texel, blending a detail map (reoriented normal mapping) and taking a
//! tangent-space normal to the surface frame.

use crate::math::Vector;
use crate::math::shading_fn;

shading_fn! {
    /// A normal-map texel (RGB in [0, 1], as normal maps store n·½ + ½) back to the tangent-space
    /// vector it encodes: 2t − 1 (Kilgard 2000; every normal-map tool's convention).
    pub fn normal_from_texel(texel: V) -> V {
        texel * 2.0 - texel.x().lit(1.0).splat()
    }
}

shading_fn! {
    /// Reoriented normal mapping (Barré-Brisebois & Hill 2012, "Blending in Detail", listing "RNM"):
    /// t = base + (0, 0, 1), u = detail·(−1, −1, 1), r = t (t·u)/t.z − u. Guard: t.z = base.z + 1
    /// ≥ 10⁻⁶ (a base pointing straight down, which no normal map stores).
    ///
    /// The detail normal is rotated by the rotation that takes +z to `base`, so the detail follows the
    /// base's slopes instead of being added to them (UDN/whiteout flatten strong details). A flat
    /// detail (0, 0, 1) returns `base`; a flat base returns `detail`.
    pub fn rnm_blend(base: V, detail: V) -> V {
        let one = base.x().lit(1.0);
        let t = base + F::vec3(one.lit(0.0), one.lit(0.0), one);
        let u = detail * F::vec3(-one, -one, one);
        let tz = t.z().at_least(1e-6);
        (t * (t.dot(u) / tz) - u).normalize()
    }
}

shading_fn! {
    /// A tangent-space normal `m` in the surface frame (tangent `t`, bitangent `b`, normal `n`):
    /// normalize(t·m.x + b·m.y + n·m.z) (Mikkelsen 2008's convention for per-pixel frames).
    pub fn tangent_to_world(m: V, t: V, b: V, n: V) -> V {
        (t * m.x() + b * m.y() + n * m.z()).normalize()
    }
}
