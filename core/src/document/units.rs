//! The document's length unit: what one model unit is. The `.taut` keeps it (key `units`,
//! absent for millimetres, the default, so older files read as they always did); the editor
//! shows lengths with it and STEP export declares it unless told otherwise.

use serde::{Deserialize, Serialize};

/// A length unit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum LengthUnit {
    #[default]
    #[serde(rename = "mm")]
    Millimetre,
    #[serde(rename = "cm")]
    Centimetre,
    #[serde(rename = "m")]
    Metre,
    #[serde(rename = "in")]
    Inch,
}

impl LengthUnit {
    pub const ALL: [LengthUnit; 4] =
        [LengthUnit::Millimetre, LengthUnit::Centimetre, LengthUnit::Metre, LengthUnit::Inch];

    /// The symbol lengths are written with, and the command line's name for it.
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Millimetre => "mm",
            LengthUnit::Centimetre => "cm",
            LengthUnit::Metre => "m",
            LengthUnit::Inch => "in",
        }
    }

    /// The unit's name in words.
    pub fn name(self) -> &'static str {
        match self {
            LengthUnit::Millimetre => "millimetres",
            LengthUnit::Centimetre => "centimetres",
            LengthUnit::Metre => "metres",
            LengthUnit::Inch => "inches",
        }
    }

    /// A length in this unit, as the editor shows it: four decimals and the symbol.
    pub fn length(self, x: f64) -> String {
        format!("{:.4} {}", if x == 0.0 { 0.0 } else { x }, self.symbol())
    }
}

impl std::str::FromStr for LengthUnit {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        LengthUnit::ALL
            .into_iter()
            .find(|u| u.symbol() == s)
            .ok_or_else(|| format!("unknown unit '{s}' (use mm, cm, m or in)"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symbols_parse_back_and_lengths_carry_them() {
        for unit in LengthUnit::ALL {
            assert_eq!(unit.symbol().parse::<LengthUnit>(), Ok(unit));
            assert_eq!(serde_json::to_string(&unit).unwrap(), format!("\"{}\"", unit.symbol()));
        }
        assert!("ft".parse::<LengthUnit>().unwrap_err().contains("mm, cm, m or in"));
        assert_eq!(LengthUnit::Inch.length(-0.0), "0.0000 in");
        assert_eq!(LengthUnit::default().length(2.5), "2.5000 mm");
    }
}
