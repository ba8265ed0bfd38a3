"""python -m fibreshell: the ``fibreshell`` command (fibreshell/cli.py)."""

import sys

from fibreshell.cli import main

sys.exit(main())
