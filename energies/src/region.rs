//! Implicit regions {x : g(x) ≤ 0} inside a bounding box, with closest-point projection.
