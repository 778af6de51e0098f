"""``python -m cadartifact``: the console script."""

from .cli import main

main()
