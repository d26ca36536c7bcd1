//! IEEE Std 952 noise-term fit (to be written).
