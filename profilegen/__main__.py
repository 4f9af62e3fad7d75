"""`python -m profilegen` is the `profilegen` command."""

import sys

from .cli import main

sys.exit(main())
