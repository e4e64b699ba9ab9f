"""``python -m wavepoly`` runs the command-line tool."""

from .cli import main

main()
