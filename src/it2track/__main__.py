"""``python -m it2track``: the ``it2track`` command line."""

from .cli.main import main

if __name__ == "__main__":  # pragma: no branch
    main(prog_name="it2track")
