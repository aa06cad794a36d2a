//! The mission's own program, as a generated project's: `cargo run -p
//! geodesic-mission-drag-free-cubesat -- verify --reports reports` verifies the housing against
//! its requirements (the `geodesic` program does the same with `--mission drag-free-cubesat`).

fn main() -> std::process::ExitCode {
    geodesic_verify::harness::main(geodesic_mission_drag_free_cubesat::mission())
}
