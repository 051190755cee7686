//! File input and output of point sets.
