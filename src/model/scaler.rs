//! Scaler (to be written).
