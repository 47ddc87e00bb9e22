"""``vid-eval view``: a run in the Rerun viewer (issue #25) - trajectory, force arrows, tracked
features, camera images - from a finished vid_run folder or live from vid_live's LCM output."""
