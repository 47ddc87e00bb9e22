"""``python -m vid_eval.importer`` = ``vid-import``."""
import sys

from .cli import main

sys.exit(main())
