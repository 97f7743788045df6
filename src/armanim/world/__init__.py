"""The world around the arm: obstacles and exact distances from the arm's parts to them (pure core)."""
