"""``python -m diffsense`` runs the ``diffsense`` command."""

from diffsense.cli.app import run

run()
