"""``python -m cadartifact.cli``: the console script."""

from . import main

main()
