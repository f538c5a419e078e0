//! Shape measures.
