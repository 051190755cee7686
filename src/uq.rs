//! Two stochastic simulation problems of the paper (Section 5.3) with their own Monte Carlo references.
