//! PD-BEM coupling (seed 002 section 2.3): tip windows, interface maps, Algorithm 1 and 2. Not built yet (issue 4).
