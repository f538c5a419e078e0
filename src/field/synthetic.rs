//! Built-in demo fields.
