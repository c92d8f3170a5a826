//! Saiho system tests: see `tests/` for tests that run the real binaries (`cloth-sim run`,
//! `haptic-loop`) in isolated iceoryx2 domains with the simulated pen.
