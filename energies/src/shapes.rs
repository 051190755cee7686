//! Built-in regions with exact closest points: ball, ellipsoid, box, simplex, polytope.
