"""``python3 -m wish_client ...`` is ``wish-client ...``."""
import sys

from .cli import main

sys.exit(main())
