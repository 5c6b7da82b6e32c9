//! Burton-Miller dual boundary integral solver with straight constant elements (seed 002 section 2.2).
