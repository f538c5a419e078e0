//! VTK reading.
