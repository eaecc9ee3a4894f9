"""``python -m diffsense.cli`` runs the ``diffsense`` command."""

from diffsense.cli.app import main

main()
