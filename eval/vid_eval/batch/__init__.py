"""vid-batch: batch evaluation on Ray."""
