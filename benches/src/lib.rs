//! Criterion benchmarks of geodesic live in `benches/benches/`; this library is empty.
