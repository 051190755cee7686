//! Reading what users type: region expressions g(x) ≤ 0 ([`expr`]) and linear
//! constraints ([`constraint`]). Each reports a refusal at the place in the text where it
//! was found.

pub mod constraint;
pub mod expr;
