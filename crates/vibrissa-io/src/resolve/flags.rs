//! The values a caller gives over a scene file: the command line's flags as typed (text),
//! or numbers given in code (the Python package's keywords, a Rust program). A text value
//! is parsed here, so that a bad value is reported naming the flag with the value as typed
//! ([`super::parse_number`]); a number goes to the model as is (no text in between), and
//! `inf`, `nan` or negative numbers reach the model's own range checks either way. Plain
//! structs, no command-line parser: the CLI fills them from its flags.

use crate::error::IoError;
use crate::scene_file::LoadKind;

/// One value given over a scene file: typed text (a flag) or a number given in code.
///
/// Messages name it as given: the text as typed, a number in Rust's shortest round-trip
/// form (`0.001`, `1000000000.0`, `NaN`), an integer in decimal.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// Text as typed on a command line (`--theta 0.75`), parsed when resolved.
    Text(String),
    /// A number given in code, used bit for bit.
    Number(f64),
    /// An integer given in code (a count: `n`, `points`, `starts`).
    Integer(i64),
}

impl Value {
    /// The value as messages show it (the text as typed; a number's shortest round-trip
    /// form).
    pub fn raw(&self) -> String {
        match self {
            Value::Text(s) => s.clone(),
            Value::Number(x) => format!("{x:?}"),
            Value::Integer(n) => n.to_string(),
        }
    }

    /// The value as a number: text parsed (refused naming `flag`), a number as is.
    pub fn number(&self, flag: &'static str) -> Result<f64, IoError> {
        match self {
            Value::Text(s) => super::parse_number(flag, s),
            Value::Number(x) => Ok(*x),
            Value::Integer(n) => Ok(*n as f64),
        }
    }

    /// The value as a count of at least `min` and at most [`super::MAX_COUNT`] (refused
    /// naming `flag` otherwise); a number must be a whole non-negative one.
    pub fn count(&self, flag: &'static str, min: usize) -> Result<usize, IoError> {
        match self {
            Value::Text(s) => super::parse_count(flag, s, min),
            Value::Number(x) if x.fract() == 0.0 && *x >= 0.0 && *x <= u32::MAX as f64 => {
                super::parse_count(flag, &(*x as u64).to_string(), min)
            }
            Value::Integer(n) if *n >= 0 => super::parse_count(flag, &n.to_string(), min),
            other => Err(IoError::invalid_argument(
                flag,
                other.raw(),
                "not a non-negative integer",
            )),
        }
    }

    /// Whether this is the keyword `word` (text, any case, spaces trimmed).
    pub fn is_word(&self, word: &str) -> bool {
        matches!(self, Value::Text(s) if s.trim().eq_ignore_ascii_case(word))
    }
}

impl From<f64> for Value {
    fn from(x: f64) -> Self {
        Value::Number(x)
    }
}

impl From<i64> for Value {
    fn from(n: i64) -> Self {
        Value::Integer(n)
    }
}

impl From<String> for Value {
    fn from(s: String) -> Self {
        Value::Text(s)
    }
}

impl From<&str> for Value {
    fn from(s: &str) -> Self {
        Value::Text(s.to_string())
    }
}

/// Whisker values (`--theta`, `--a`, `--b`, `--k`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WhiskerFlags {
    /// Taper, the diameter ratio tip/base.
    pub theta: Option<Value>,
    /// Slope A of the pre-curvature kappa0(s) = A s + B.
    pub a: Option<Value>,
    /// Offset B of the pre-curvature.
    pub b: Option<Value>,
    /// Base stiffness (`inf` for a rigid support).
    pub k: Option<Value>,
}

/// Tip-force values (`--f`, `--beta-deg`, `--load`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TipFlags {
    /// Tip force magnitude.
    pub f: Option<Value>,
    /// Tip force angle in degrees.
    pub beta_deg: Option<Value>,
    /// Direction- or angle-preserving tip force.
    pub load: Option<LoadKind>,
}

/// Fluid-load values (`--q`, `--alpha-deg`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FluidFlags {
    /// Fluid load per unit length.
    pub q: Option<Value>,
    /// Fluid load angle in degrees.
    pub alpha_deg: Option<Value>,
}

/// Method values (`--method`, `--n`, `--tol`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MethodFlags {
    /// Method name (`accurate`, `auto`, `rk4`, `fdm`, `fdm-richardson`,
    /// `multiple-shooting`, `collocation`).
    pub method: Option<String>,
    /// Grid intervals.
    pub n: Option<Value>,
    /// The accuracy asked of `auto`.
    pub tol: Option<Value>,
}

/// All model values of `solve` and `sweep`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ModelFlags {
    /// Whisker values.
    pub whisker: WhiskerFlags,
    /// Tip force values.
    pub tip: TipFlags,
    /// Fluid load values.
    pub fluid: FluidFlags,
    /// Method values.
    pub method: MethodFlags,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xorshift64*: a seeded stream of bit patterns, no dependency.
    fn bits(seed: &mut u64) -> u64 {
        *seed ^= *seed >> 12;
        *seed ^= *seed << 25;
        *seed ^= *seed >> 27;
        seed.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    #[test]
    fn a_number_given_in_code_is_the_number_typed_bit_for_bit() {
        // every f64 pattern (NaN payloads aside): the number as given, its message form
        // typed back as a flag, and the same bits out of both
        let mut seed = 0x5eed_0035_u64;
        for _ in 0..20_000 {
            let x = f64::from_bits(bits(&mut seed));
            let given = Value::Number(x);
            let typed = Value::Text(given.raw());
            let (a, b) = (given.number("--q").unwrap(), typed.number("--q").unwrap());
            if x.is_nan() {
                assert!(a.is_nan() && b.is_nan());
            } else {
                assert_eq!(a.to_bits(), x.to_bits());
                assert_eq!(b.to_bits(), x.to_bits(), "{x:?} typed back");
            }
        }
    }

    #[test]
    fn counts_are_whole_and_named_as_given() {
        assert_eq!(Value::Integer(7).count("--n", 4).unwrap(), 7);
        assert_eq!(Value::Number(4.0).count("--starts", 1).unwrap(), 4);
        assert_eq!(Value::Text(" 12 ".into()).count("--n", 0).unwrap(), 12);
        let msg = |v: Value| v.count("--n", 4).unwrap_err().to_string();
        assert_eq!(
            msg(Value::Integer(-1)),
            "invalid value `-1` for `--n`: not a non-negative integer"
        );
        assert_eq!(
            msg(Value::Number(2.5)),
            "invalid value `2.5` for `--n`: not a non-negative integer"
        );
        assert_eq!(
            msg(Value::Number(f64::NAN)),
            "invalid value `NaN` for `--n`: not a non-negative integer"
        );
        assert_eq!(
            msg(Value::Integer(2)),
            "invalid value `2` for `--n`: must be at least 4"
        );
        assert_eq!(
            msg(Value::Text("x".into())),
            "invalid value `x` for `--n`: not a non-negative integer"
        );
        assert!(Value::Text(" None ".into()).is_word("none"));
        assert!(!Value::Number(0.0).is_word("none"));
    }
}
