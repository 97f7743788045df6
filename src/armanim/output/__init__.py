"""Writing and reading run outputs: atomic files, trajectory.csv, summary.json."""
