"""``python -m armanim``: the same as the ``armanim`` command."""

from armanim.cli import main

if __name__ == "__main__":
    main()
