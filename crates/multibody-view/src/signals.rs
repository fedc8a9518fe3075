//! Which signals a view shows: the user's patterns, or a guess at the
//! state-like ones.

use crate::ViewError;
use multibody::Solution;

/// How many signals the guess picks.
const DEFAULT_COUNT: usize = 6;

/// The signals matching `patterns` (`*` and `?` wildcards, e.g. `*.phi`,
/// `body.r_0[*]`), in pattern order and then solution order, without
/// repeats; a guess ([`default_signals`]) when `patterns` is empty. A
/// pattern that matches nothing is an error that suggests close names.
pub fn choose_signals(solution: &Solution, patterns: &[String]) -> Result<Vec<String>, ViewError> {
    if patterns.is_empty() {
        return Ok(default_signals(solution));
    }
    let mut chosen: Vec<String> = Vec::new();
    for pattern in patterns {
        let matches = solution.select(std::slice::from_ref(pattern));
        if matches.is_empty() {
            let names = solution.names().iter().map(String::as_str);
            let close = multibody::closest(pattern, names);
            let hint = if close.is_empty() {
                let examples: Vec<&str> = solution.names().iter().take(4).map(String::as_str).collect();
                if examples.is_empty() {
                    String::new()
                } else {
                    format!(" (signals look like {}; `*` matches any text)", examples.join(", "))
                }
            } else {
                format!(" (did you mean {}?)", close.join(", "))
            };
            return Err(ViewError::NoSignal { pattern: pattern.clone(), hint });
        }
        for m in matches {
            if !chosen.iter().any(|c| c == m) {
                chosen.push(m.to_string());
            }
        }
    }
    Ok(chosen)
}

/// A guess at the signals worth plotting when none were asked for: joint
/// coordinates (`rev.phi`, `prism.s`, Euler angles `body.phi[i]`), then
/// their rates (`rev.w`, `prism.v`), then free bodies' positions
/// (`body.r_0[i]`), then whatever comes first; at most six.
pub fn default_signals(solution: &Solution) -> Vec<String> {
    let names = solution.names();
    // Component-level variables: `comp.var` or `comp.var[i]` (components of
    // user models have dotted names, `pend.joint.phi`), not connector
    // variables like `comp.frame_a.f[1]`.
    let split = |n: &str| -> Option<(String, String)> {
        let (component, var) = n.rsplit_once('.')?;
        let last = component.rsplit('.').next().unwrap_or(component);
        if last.starts_with("frame_") {
            return None;
        }
        let base = var.split('[').next().unwrap_or(var).to_string();
        Some((component.to_string(), base))
    };
    let mut out: Vec<String> = Vec::new();
    let mut coordinates: Vec<(String, String)> = Vec::new();
    for n in names {
        if let Some((c, v)) = split(n) {
            if v == "phi" || v == "s" {
                out.push(n.clone());
                coordinates.push((c, v));
            }
        }
    }
    if out.len() < DEFAULT_COUNT {
        for n in names {
            if let Some((c, v)) = split(n) {
                let rate = match v.as_str() {
                    "w" => "phi",
                    "v" => "s",
                    "phid" => "phi",
                    _ => continue,
                };
                if coordinates.iter().any(|(cc, cv)| *cc == c && cv == rate) {
                    out.push(n.clone());
                }
            }
        }
    }
    if out.is_empty() {
        out.extend(names.iter().filter(|n| split(n).is_some_and(|(_, v)| v == "r_0")).cloned());
    }
    if out.is_empty() {
        out.extend(names.iter().filter(|n| split(n).is_some()).cloned());
    }
    if out.is_empty() {
        out.extend(names.iter().cloned());
    }
    out.truncate(DEFAULT_COUNT);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solution(names: &[&str]) -> Solution {
        let mut s = Solution::new(names.iter().map(|n| n.to_string()).collect(), vec![""; names.len()]);
        s.push(0.0, &vec![0.0; names.len()]);
        s
    }

    #[test]
    fn guesses_joint_coordinates_then_rates() {
        let s =
            solution(&["world.frame_b.f[1]", "rev.phi", "rev.w", "rev.frame_a.r_0[1]", "damper.phi_rel", "p.s", "p.v"]);
        assert_eq!(default_signals(&s), ["rev.phi", "p.s", "rev.w", "p.v"]);
    }

    #[test]
    fn guesses_body_positions_without_joints() {
        let s = solution(&["body.frame_a.r_0[1]", "body.r_0[1]", "body.r_0[2]", "body.v_0[1]"]);
        assert_eq!(default_signals(&s), ["body.r_0[1]", "body.r_0[2]"]);
    }

    #[test]
    fn patterns_keep_order_and_suggest_names() {
        let s = solution(&["a.phi", "b.phi", "a.w"]);
        let chosen = choose_signals(&s, &["a.w".into(), "*.phi".into()]).unwrap();
        assert_eq!(chosen, ["a.w", "a.phi", "b.phi"]);
        let err = choose_signals(&s, &["a.pih".into()]).unwrap_err().to_string();
        assert!(err.contains("a.pih") && err.contains("a.phi"), "{err}");
    }
}
