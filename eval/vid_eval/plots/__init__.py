"""PNG plots of the evaluation results (matplotlib, Agg backend, no display needed)."""
