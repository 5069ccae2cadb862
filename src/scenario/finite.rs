//! Numbers that are not numbers: TOML writes `nan` and `inf` as floats, which every range check
//! written `v < lo || v > hi` lets through (a NaN compares false). Every such value in a scene
//! is refused where it is written, naming its key and line — before any check of the key's own
//! could miss it (`at_m = [nan, 0, 0]` failed later as "singular wheelset equations").

/// Every `nan` or `inf` value of the TOML `text` (outside strings and comments): its line
/// (1-based), the key it is assigned to (the nearest `key =` before it on its line, else the last
/// one before: an array's continuation line) and the token.
pub fn non_finite_values(text: &str) -> Vec<(usize, String, String)> {
    let mut found = Vec::new();
    let mut last_key = String::new();
    for (n, line) in text.lines().enumerate() {
        let bytes = line.as_bytes();
        let mut i = 0;
        let mut key_here: Option<String> = None;
        let mut quote: Option<u8> = None;
        let mut word_start: Option<usize> = None;
        while i <= bytes.len() {
            let c = bytes.get(i).copied();
            if let Some(q) = quote {
                if c == Some(b'\\') && q == b'"' {
                    i += 2;
                    continue;
                }
                if c == Some(q) {
                    quote = None;
                }
                i += 1;
                continue;
            }
            let is_word = matches!(c, Some(b) if b.is_ascii_alphanumeric() || b == b'_' || b == b'-' || b == b'+' || b == b'.');
            if is_word {
                word_start.get_or_insert(i);
                i += 1;
                continue;
            }
            if let Some(s) = word_start.take() {
                let word = &line[s..i];
                if line[i..].trim_start().starts_with('=') {
                    let key = word.rsplit('.').next().unwrap_or(word).to_string();
                    key_here = Some(key);
                } else {
                    let bare = word.trim_start_matches(['+', '-']);
                    if bare == "nan" || bare == "inf" {
                        let key = key_here.clone().unwrap_or_else(|| {
                            if last_key.is_empty() {
                                "a value".to_string()
                            } else {
                                last_key.clone()
                            }
                        });
                        found.push((n + 1, key, word.to_string()));
                    }
                }
            }
            match c {
                None | Some(b'#') => break,
                Some(b'"') | Some(b'\'') => quote = c,
                _ => {}
            }
            i += 1;
        }
        if let Some(k) = key_here {
            last_key = k;
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nan_and_inf_are_found_with_their_key_and_line() {
        let text = "a = 1.0\nat_m = [nan, 0.0, 1.0] # inf in a comment\nname = \"nan inf\"\nb = -inf\nc = [\n  1.0,\n  +nan,\n]\nd = { x = 1.0, y = inf }\n";
        let f = non_finite_values(text);
        assert_eq!(
            f,
            vec![
                (2, "at_m".to_string(), "nan".to_string()),
                (4, "b".to_string(), "-inf".to_string()),
                (7, "c".to_string(), "+nan".to_string()),
                (9, "y".to_string(), "inf".to_string()),
            ]
        );
        assert!(non_finite_values("inf = 1.0\ninfo = 2\nnanny = 3.0\n").is_empty());
    }
}
