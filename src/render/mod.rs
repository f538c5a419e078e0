//! GPU renderers.
