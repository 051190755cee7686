//! Classic point sequences: starts for the DEM and baselines to compare with.
