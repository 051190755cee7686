//! Reading what users type, every grammar of the project in one place: region expressions
//! g(x) ≤ 0 ([`expr`]) and linear constraints ([`constraint`]) over one lexer (`lexer`);
//! boxes, bounds and the built-in shapes ([`space`]); design variables `NAME=TYPE`
//! ([`design`]). Each refusal names the option as the caller spells it and echoes the
//! text. [`names`] holds the option names that layers below the option table spell.

#![deny(missing_docs)]

pub mod constraint;
pub mod design;
pub mod expr;
pub(crate) mod lexer;
pub mod names;
pub mod space;
