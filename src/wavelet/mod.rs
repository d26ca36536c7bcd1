//! Wavelets (to be written).
