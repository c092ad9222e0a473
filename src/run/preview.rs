//! Sphere previews (filled in below).
