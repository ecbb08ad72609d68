//! Closed plate motion: see issue 3 (owned by the motion/simulator work).
