//! argmin L-BFGS as an integrator, on the same energies and domains as the DEM.
