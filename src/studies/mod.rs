//! The paper's studies, each reproducible by one command.
