"""vid_live / vid_replay helpers: fault bookkeeping and the one-hour soak (`vid-soak`)."""
