//! Streaming building blocks (to be written).
