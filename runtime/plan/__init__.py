"""Planning: a motion command → profiled segments → a setpoint every IPO cycle."""
