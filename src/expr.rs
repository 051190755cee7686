//! Region expressions g(x1, …, xs) from the command line.
