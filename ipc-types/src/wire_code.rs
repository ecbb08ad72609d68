//! Enums carried on the wire as `u32` codes, never as Rust enums (a Rust
//! enum read from shared memory with an unknown discriminant would be
//! undefined behaviour): each value with its code and its name, and the
//! checked way back from a code.

/// `wire_code! { /// doc
/// pub enum Name { /// doc
/// Variant = code => "name", … } }` defines the enum and `ALL` (in code
/// order), `code()`, `from_code()` (`None` for an unknown code),
/// `as_str()` and `Display` (the name).
macro_rules! wire_code {
    (
        $(#[$meta:meta])*
        pub enum $name:ident {
            $($(#[$vmeta:meta])* $variant:ident = $code:literal => $text:literal,)+
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $name {
            $($(#[$vmeta])* $variant = $code,)+
        }

        impl $name {
            /// Every value, in code order.
            pub const ALL: [Self; [$($code),+].len()] = [$(Self::$variant),+];

            pub const fn code(self) -> u32 {
                self as u32
            }

            /// The value of a wire code, `None` for an unknown code.
            pub const fn from_code(code: u32) -> Option<Self> {
                match code {
                    $($code => Some(Self::$variant),)+
                    _ => None,
                }
            }

            /// The name `upm status`, JSON and the docs use.
            pub const fn as_str(self) -> &'static str {
                match self {
                    $(Self::$variant => $text,)+
                }
            }
        }

        impl core::fmt::Display for $name {
            fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str(self.as_str())
            }
        }
    };
}

pub(crate) use wire_code;
