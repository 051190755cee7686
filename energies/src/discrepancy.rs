//! The L2 discrepancies as energies: squared star, modified, centred and wrap-around L2 with their gradients.
