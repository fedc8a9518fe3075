//! A small JSON writer for the page's scene description (the scene is flat
//! and known, so no serializer is needed).

use std::fmt::Write;

pub struct Json {
    out: String,
    /// Per open container: whether the next item needs a comma.
    comma: Vec<bool>,
    /// A key was just written: the value that follows takes no comma.
    after_key: bool,
}

impl Json {
    pub fn new() -> Self {
        Self { out: String::new(), comma: vec![false], after_key: false }
    }

    pub fn finish(self) -> String {
        self.out
    }

    fn separate(&mut self) {
        if std::mem::take(&mut self.after_key) {
            return;
        }
        if let Some(c) = self.comma.last_mut() {
            if *c {
                self.out.push(',');
            }
            *c = true;
        }
    }

    pub fn key(&mut self, key: &str) -> &mut Self {
        self.separate();
        write_string(&mut self.out, key);
        self.out.push(':');
        self.after_key = true;
        self
    }

    pub fn begin_object(&mut self) -> &mut Self {
        self.separate();
        self.out.push('{');
        self.comma.push(false);
        self
    }

    pub fn end_object(&mut self) -> &mut Self {
        self.comma.pop();
        self.out.push('}');
        self
    }

    pub fn begin_array(&mut self) -> &mut Self {
        self.separate();
        self.out.push('[');
        self.comma.push(false);
        self
    }

    pub fn end_array(&mut self) -> &mut Self {
        self.comma.pop();
        self.out.push(']');
        self
    }

    pub fn string(&mut self, s: &str) -> &mut Self {
        self.separate();
        write_string(&mut self.out, s);
        self
    }

    pub fn number(&mut self, x: f64) -> &mut Self {
        self.separate();
        write_number(&mut self.out, x);
        self
    }

    pub fn boolean(&mut self, b: bool) -> &mut Self {
        self.separate();
        self.out.push_str(if b { "true" } else { "false" });
        self
    }

    pub fn numbers(&mut self, xs: &[f64]) -> &mut Self {
        self.begin_array();
        for &x in xs {
            self.number(x);
        }
        self.end_array()
    }
}

fn write_string(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            // Escaped `<`, `>` and `&` keep `</script>` out of the embedded text.
            '<' | '>' | '&' | '\u{2028}' | '\u{2029}' => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

/// A finite number as JSON; NaN and infinities (not JSON) as `null`.
fn write_number(out: &mut String, x: f64) {
    if !x.is_finite() {
        out.push_str("null");
    } else if x == 0.0 {
        out.push('0');
    } else if (1e-5..1e15).contains(&x.abs()) {
        let _ = write!(out, "{x}");
    } else {
        let _ = write!(out, "{x:e}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nested_values() {
        let mut j = Json::new();
        j.begin_object();
        j.key("a").number(1.5);
        j.key("b").begin_array().string("x</script>").boolean(true).number(f64::NAN).end_array();
        j.key("c").begin_object().key("d").numbers(&[1e-9, 2.0, -3e20]).end_object();
        j.end_object();
        assert_eq!(j.finish(), r#"{"a":1.5,"b":["x\u003c/script\u003e",true,null],"c":{"d":[1e-9,2,-3e20]}}"#);
    }
}
