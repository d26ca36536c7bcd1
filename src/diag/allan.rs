//! Overlapping Allan deviation (to be written).
