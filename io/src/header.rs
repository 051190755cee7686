//! The header lines that start every text file this crate writes: `# stillpoint
//! <version>`, then one `# key: value` line per entry of the run's provenance. Readers
//! skip them as comments.

use std::fmt::Write as _;

/// Appends `# stillpoint <version>` and the lines of `meta` ([`crate::push_meta_comments`]).
pub fn push_header(out: &mut String, meta: &serde_json::Value) {
    let _ = writeln!(out, "# stillpoint {}", env!("CARGO_PKG_VERSION"));
    push_meta_comments(out, meta);
}

/// One `# key: value` line per entry of a JSON object; any other non-null value becomes a
/// single `# meta: value` line.
pub fn push_meta_comments(out: &mut String, meta: &serde_json::Value) {
    let mut line = |key: &str, value: &serde_json::Value| {
        // A newline in a key would end the comment and corrupt the data that follows.
        let key: String = key
            .chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect();
        let _ = writeln!(out, "# {key}: {value}");
    };
    match meta {
        serde_json::Value::Null => {}
        serde_json::Value::Object(map) => map.iter().for_each(|(k, v)| line(k, v)),
        other => line("meta", other),
    }
}
