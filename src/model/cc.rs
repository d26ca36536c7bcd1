//! C-C method (to be written).
