"""python3 -m riffle_tools COMMAND ...: the same as tools/riffle-tools."""
import sys

from .cli import main

sys.exit(main())
