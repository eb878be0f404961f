"""Public API: compile_program, run_program, load_robot (filled by the areas)."""
