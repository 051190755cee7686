//! Boundary-aware energies for regions: U_{E,∞,g} (eqs. 56–57) and a smooth finite-p variant.
