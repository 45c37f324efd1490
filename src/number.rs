//! Numbers as shotdamp compares and shows them: the tolerance of a comparison, and the one
//! way a value is written in tables, checks and file keys. A leaf: it imports nothing of
//! shotdamp, so that experiment files and checks can both use it.

/// A tolerance: pass when `|computed - expected| <= abs + rel |expected|`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// Relative part.
    pub rel: f64,
    /// Absolute part, in the value's unit.
    pub abs: f64,
}

/// `v` to `digits` significant digits, trailing zeros dropped (`fmt_sig(6.917275, 2)` is
/// "6.9"): a value shown to the precision that matters, as a clearance where the objective is
/// flat.
pub fn fmt_sig(v: f64, digits: u32) -> String {
    if v == 0.0 || !v.is_finite() {
        return fmt_num(v);
    }
    let magnitude = v.abs().log10().floor() as i32;
    let decimals = (digits as i32 - 1 - magnitude).max(0) as usize;
    let scale = 10f64.powi(digits as i32 - 1 - magnitude);
    let rounded = (v * scale).round() / scale;
    let s = format!("{rounded:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Number formatting shared by tables and checks.
pub fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        "0".to_string()
    } else if !v.is_finite() {
        format!("{v}")
    } else if v.abs() >= 1e-3 && v.abs() < 1e5 {
        let s = format!("{v:.6}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        format!("{v:.5e}")
    }
}

/// A list of numbers as `[a, b, c]`, each as [`fmt_num`] writes it (never a 300-digit
/// decimal, never `Some(..)`).
pub fn fmt_list(values: &[f64]) -> String {
    let parts: Vec<String> = values.iter().map(|v| fmt_num(*v)).collect();
    format!("[{}]", parts.join(", "))
}

/// `x` rounded to 15 significant digits: a quantity derived from decimal inputs (a ratio
/// times a sum of masses) as the decimal it stands for, so that 0.1 x 11.5 is 1.15 and not
/// the product's rounding 1.1500000000000001 (they differ by at most 5e-15 of `x`; a value
/// the inputs give exactly is unchanged).
pub fn decimal(x: f64) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    format!("{x:.14e}").parse().unwrap_or(x)
}

/// `text` with every decimal number longer than 20 characters (how `Display` writes 1e-320 or
/// 1e300) written as [`fmt_num`] writes it: messages quote values as a person reads them.
pub fn tidy_numbers(text: &str) -> String {
    tidy(text, false)
}

/// A value as a message quotes it: [`tidy_numbers`], and control characters (a newline or tab
/// inside a quoted string) escaped as a TOML file writes them (`\n`, `\t`, `\u001B`), so that
/// the message stays one line that reads as the file does.
pub fn tidy_value(text: &str) -> String {
    tidy(text, true)
}

fn tidy(text: &str, controls: bool) -> String {
    let mut out = String::with_capacity(text.len());
    let mut run = String::new();
    let flush = |run: &mut String, out: &mut String| {
        match run.parse::<f64>() {
            Ok(v) if run.len() > 20 && run.bytes().any(|b| b.is_ascii_digit()) => out.push_str(&fmt_num(v)),
            _ => out.push_str(run),
        }
        run.clear();
    };
    for c in text.chars() {
        if controls && c.is_control() {
            flush(&mut run, &mut out);
            match c {
                '\n' => out.push_str("\\n"),
                '\t' => out.push_str("\\t"),
                '\r' => out.push_str("\\r"),
                other => out.push_str(&format!("\\u{:04X}", other as u32)),
            }
            continue;
        }
        let continues = c.is_ascii_digit() || c == '.' || (c == '-' && run.is_empty());
        if continues {
            run.push(c);
        } else {
            flush(&mut run, &mut out);
            out.push(c);
        }
    }
    flush(&mut run, &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_derived_decimal_reads_as_the_decimal() {
        assert_eq!((0.1 * 11.5).to_string(), "1.1500000000000001");
        assert_eq!(decimal(0.1 * 11.5).to_string(), "1.15");
        // A decimal of at most 15 digits is left as it is; any other value moves by at most
        // 5e-15 of itself (half a unit of the 15th digit).
        for x in [0.209, 0.25, 1e-300, -2.5e12, 0.0, 123456789012345.0] {
            assert_eq!(decimal(x), x, "{x}");
        }
        for x in [1.0 / 3.0, std::f64::consts::PI, 0.1 * 11.5] {
            assert!((decimal(x) - x).abs() <= 5e-15 * x, "{x}");
        }
        assert!(decimal(f64::NAN).is_nan());
    }

    #[test]
    fn significant_digits() {
        assert_eq!(fmt_sig(6.917275, 2), "6.9");
        assert_eq!(fmt_sig(0.0123456, 2), "0.012");
        assert_eq!(fmt_sig(99.6, 2), "100");
        assert_eq!(fmt_sig(123.4, 2), "120");
        assert_eq!(fmt_sig(5.016441, 3), "5.02");
        assert_eq!(fmt_sig(2.0, 2), "2");
        assert_eq!(fmt_sig(-0.864402, 3), "-0.864");
    }

    #[test]
    fn long_decimals_are_written_short_and_the_rest_is_kept() {
        let tiny = format!("invalid type: floating point `{}`, expected a string", 1e-320);
        assert_eq!(tidy_numbers(&tiny), "invalid type: floating point `9.99989e-321`, expected a string");
        let huge = format!("value {} and 12.5 and -3 in cases[2]", 1e300);
        assert_eq!(tidy_numbers(&huge), "value 1.00000e300 and 12.5 and -3 in cases[2]");
        assert_eq!(tidy_numbers("a-b 2026-11-26 x.y"), "a-b 2026-11-26 x.y");
        assert_eq!(fmt_list(&[0.5, 1e-320, 2.0]), "[0.5, 9.99989e-321, 2]");
        assert_eq!(tidy_value("\"a\tb\nc\u{1b}\""), "\"a\\tb\\nc\\u001B\"");
        assert_eq!(tidy_numbers("line 1\nline 2"), "line 1\nline 2", "a message's own lines are kept");
    }
}
