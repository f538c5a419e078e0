//! Enums whose values have names (command-line values, JSON, the viewer's labels): one macro
//! gives each its list of names, `name()`, `Display` and `FromStr`, so the library needs no
//! command-line parser and every front end spells the values the same way.

/// `named_values!(Type { Variant => "name", … })`.
macro_rules! named_values {
    ($ty:ident { $($variant:ident => $name:literal),+ $(,)? }) => {
        impl $ty {
            /// Every value, in declaration order.
            pub const VALUES: &'static [$ty] = &[$($ty::$variant),+];
            /// Every value's name, in declaration order.
            pub const NAMES: &'static [&'static str] = &[$($name),+];

            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.pad(self.name())
            }
        }

        impl std::str::FromStr for $ty {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                match s {
                    $($name => Ok($ty::$variant),)+
                    _ => Err(format!("'{s}' is not one of {}", Self::NAMES.join(", "))),
                }
            }
        }
    };
}

pub(crate) use named_values;
