"""``python -m adcskit`` runs the command-line interface."""

from adcskit.cli import main

raise SystemExit(main())
