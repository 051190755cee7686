//! U_{E,∞}: the inverse minimum distance, with its active-pair subgradient (eq. 19).
