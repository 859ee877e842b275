//! Numbers for the `--json` outputs: JSON has no NaN or infinity, so such values are
//! written as `null`. The one helper every command's JSON uses.

use serde_json::Value;

/// `v` as a JSON number, `null` for NaN and infinities.
pub fn json_number(v: f64) -> Value {
    serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number)
}

/// An optional number: `null` when absent, else as [`json_number`].
pub fn json_opt(v: Option<f64>) -> Value {
    v.map_or(Value::Null, json_number)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_numbers_are_null() {
        assert_eq!(json_number(1.5), serde_json::json!(1.5));
        assert_eq!(
            json_number(-0.0).to_string(),
            serde_json::json!(-0.0).to_string()
        );
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(json_number(v), Value::Null);
        }
        assert_eq!(json_opt(None), Value::Null);
        assert_eq!(json_opt(Some(2.0)), serde_json::json!(2.0));
    }
}
