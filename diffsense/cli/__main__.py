"""``python -m diffsense.cli`` runs the ``diffsense`` command."""

from diffsense.cli.app import run

if __name__ == "__main__":  # a worker process started by ``spawn`` imports this module too
    run()
