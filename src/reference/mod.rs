//! Exact f64 CPU ray caster.
