//! The grammar of design variables as users write them, `NAME=TYPE`: a name, then
//! `FUNCTION(NUMBERS)`, `int(lo,hi)`, `{a,b,c}`, `ordered{low,mid,high}` or
//! `brownian(ARGS)`. It reads the text into a [`VariableText`]; what each law's numbers
//! and a path's arguments mean is the design crate's (`stillpoint_design::DesignSpace::parse`).

use stillpoint_domains::Error;

/// The most levels one categorical variable may list (a design with more levels than
/// points cannot show each of them).
pub const MAX_LEVELS: usize = 1 << 16;

/// Every type a variable may have, as the refusals list them.
pub const TYPES: &str = "uniform(lo,hi), normal(mu,sigma), truncnormal(mu,sigma,lo,hi), \
                         lognormal(mu,sigma), beta(a,b[,lo,hi]), triangular(lo,mode,hi), \
                         int(lo,hi), {a,b,c}, ordered{low,mid,high} or \
                         brownian(T,m[,construction])";

/// One variable as written: its name and its type.
#[derive(Debug, Clone, PartialEq)]
pub struct VariableText<'a> {
    /// The name, trimmed.
    pub name: &'a str,
    /// The type.
    pub ty: TypeText<'a>,
}

/// A variable's type as written.
#[derive(Debug, Clone, PartialEq)]
pub enum TypeText<'a> {
    /// `{a,b,c}` or `ordered{low,mid,high}`: distinct labels, at most [`MAX_LEVELS`].
    Levels {
        /// The labels, trimmed.
        labels: Vec<String>,
        /// Whether `ordered` was written.
        ordered: bool,
    },
    /// `int(lo,hi)` (or `integer`): whole numbers lo ≤ hi.
    Integer {
        /// The lowest value.
        lo: i64,
        /// The highest value.
        hi: i64,
    },
    /// `FUNCTION(NUMBERS)`: a law's name in lower case and its parameters.
    Law {
        /// The function, lower case.
        func: String,
        /// Its parameters.
        numbers: Vec<f64>,
    },
    /// `brownian(ARGS)`: the text inside the parentheses.
    Brownian {
        /// The arguments as written.
        args: &'a str,
    },
}

/// Reads `item`, `NAME=TYPE`; `option` names the option in refusals (`--var`, `space`).
pub fn variable<'a>(option: &str, item: &'a str) -> Result<VariableText<'a>, Error> {
    let bad = |expected: String| Error::invalid(option, item, expected);
    let Some((name, spec)) = item.split_once('=') else {
        return Err(bad(
            "NAME=TYPE, e.g. x=uniform(0,1), k=int(1,5) or c={a,b,c}".into(),
        ));
    };
    let name = name.trim();
    let first_ok = name
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    if !first_ok
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-'))
    {
        return Err(bad(
            "a NAME of letters, digits, '_', '.' or '-' starting with a letter or '_'".into(),
        ));
    }
    let spec = spec.trim();
    if let Some(args) = spec
        .split_once('(')
        .filter(|(f, _)| f.trim().eq_ignore_ascii_case("brownian"))
        .map(|(_, rest)| rest)
    {
        let Some(args) = args.trim_end().strip_suffix(')') else {
            return Err(bad(format!(
                "{name}=brownian(...) with a closing parenthesis"
            )));
        };
        return Ok(VariableText {
            name,
            ty: TypeText::Brownian { args },
        });
    }
    let ty = if let Some(body) = braces(spec.strip_prefix("ordered").unwrap_or("")) {
        TypeText::Levels {
            labels: labels(option, item, name, body)?,
            ordered: true,
        }
    } else if let Some(body) = braces(spec) {
        TypeText::Levels {
            labels: labels(option, item, name, body)?,
            ordered: false,
        }
    } else {
        call(option, item, name, spec)?
    };
    Ok(VariableText { name, ty })
}

fn braces(spec: &str) -> Option<&str> {
    spec.trim()
        .strip_prefix('{')
        .and_then(|b| b.strip_suffix('}'))
}

/// Labels are written bare in a CSV cell, so a comma, quote, brace or line break (which
/// would change the file's columns or the grammar) is refused.
fn labels(option: &str, item: &str, name: &str, body: &str) -> Result<Vec<String>, Error> {
    let labels: Vec<String> = body.split(',').map(|l| l.trim().to_string()).collect();
    if labels.iter().any(|l| l.is_empty()) {
        return Err(Error::invalid(
            option,
            item,
            format!("{name}={{a,b,...}}: one or more non-empty labels, comma-separated"),
        ));
    }
    if let Some(l) = labels.iter().find(|l| {
        l.chars()
            .any(|c| matches!(c, '"' | '{' | '}' | '\n' | '\r' | '\t'))
            || l.starts_with('#')
    }) {
        return Err(Error::invalid(
            option,
            item,
            format!(
                "labels without quotes, braces, tabs or line breaks, not starting with '#' ({l:?})"
            ),
        ));
    }
    if labels.len() > MAX_LEVELS {
        return Err(Error::invalid(
            option,
            item,
            format!("at most {MAX_LEVELS} levels"),
        ));
    }
    for (i, l) in labels.iter().enumerate() {
        if labels[..i].contains(l) {
            return Err(Error::invalid(
                option,
                item,
                format!("distinct labels, but {l} appears twice"),
            ));
        }
    }
    Ok(labels)
}

/// `FUNCTION(ARGS)`: a distribution or an integer range.
fn call(option: &str, item: &str, name: &str, spec: &str) -> Result<TypeText<'static>, Error> {
    let bad = |expected: String| Error::invalid(option, item, expected);
    let Some((func, rest)) = spec.split_once('(') else {
        return Err(bad(format!("{name}= one of {TYPES}")));
    };
    let Some(args) = rest.trim_end().strip_suffix(')') else {
        return Err(bad(format!(
            "{name}={func}(...) with a closing parenthesis"
        )));
    };
    let func = func.trim().to_ascii_lowercase();
    if func == "int" || func == "integer" {
        let ends: Vec<Option<i64>> = args.split(',').map(|a| a.trim().parse().ok()).collect();
        return match ends.as_slice() {
            [Some(lo), Some(hi)]
                if lo <= hi
                    && lo.abs() < 1 << 53
                    && hi.abs() < 1 << 53
                    && ((hi - lo) as u64) < MAX_LEVELS as u64 * 16 =>
            {
                Ok(TypeText::Integer { lo: *lo, hi: *hi })
            }
            _ => Err(bad(format!(
                "{name}=int(lo,hi): whole numbers lo ≤ hi below 2^53 in size, at most {} \
                 values",
                MAX_LEVELS * 16
            ))),
        };
    }
    let numbers: Vec<f64> = args
        .split(',')
        .map(|a| a.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad(format!("{name}={func}(...) with numbers as its parameters")))?;
    Ok(TypeText::Law { func, numbers })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_form_reads_into_its_parts() {
        let v = variable("--var", " x = Normal(0, 2.5) ").unwrap();
        assert_eq!(v.name, "x");
        assert_eq!(
            v.ty,
            TypeText::Law {
                func: "normal".into(),
                numbers: vec![0.0, 2.5]
            }
        );
        let k = variable("--var", "k=int(-3,4)").unwrap();
        assert_eq!(k.ty, TypeText::Integer { lo: -3, hi: 4 });
        let c = variable("--var", "c=ordered{low, mid,high}").unwrap();
        assert_eq!(
            c.ty,
            TypeText::Levels {
                labels: vec!["low".into(), "mid".into(), "high".into()],
                ordered: true
            }
        );
        let w = variable("space", "W=brownian(1,64,pca)").unwrap();
        assert_eq!(
            (w.name, w.ty),
            ("W", TypeText::Brownian { args: "1,64,pca" })
        );
    }

    #[test]
    fn a_refusal_names_the_option_and_echoes_the_item() {
        for (item, expected) in [
            ("x", "NAME=TYPE"),
            ("1x=normal(0,1)", "a NAME of letters"),
            ("x=normal(0,1", "closing parenthesis"),
            ("x=normal(a,1)", "numbers as its parameters"),
            ("c={a,a}", "distinct labels"),
            ("k=int(5,1)", "whole numbers lo ≤ hi"),
        ] {
            let e = variable("--var", item).unwrap_err().to_string();
            assert!(
                e.contains("--var") && e.contains(item) && e.contains(expected),
                "{e}"
            );
        }
    }
}
