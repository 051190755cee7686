//! Reading what users type: region expressions g(x) ≤ 0 ([`expr`]) and linear
//! constraints ([`constraint`]), two grammars over one lexer (`lexer`). Each reports a
//! refusal at the place in the text where it was found.

#![deny(missing_docs)]

pub mod names;
pub mod space;

pub mod constraint;
pub mod design;
pub mod expr;
pub(crate) mod lexer;
