//! The eight test integrands F1–F8 of the paper (eq. 49) and integration errors of point sets.
