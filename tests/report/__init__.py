"""verify/report/: the main job and the committed reports."""
