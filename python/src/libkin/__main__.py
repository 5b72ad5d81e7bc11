"""python -m libkin: the command line (see libkin.cli)."""
import sys


def _run() -> int:
    try:
        from .cli import main
    except ImportError as exc:  # the C library could not be loaded: say so in one line
        print("libkin: " + " ".join(str(exc).split()), file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    return main()


if __name__ == "__main__":
    sys.exit(_run())
