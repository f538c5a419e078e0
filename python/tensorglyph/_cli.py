"""The ``tensorglyph`` console command: the Rust binary's command line, run by the library's
own ``cli::main`` through the extension (same options, output and exit status)."""

import sys


def main() -> None:
    from ._tensorglyph import cli_main

    sys.stdout.flush()
    sys.stderr.flush()
    sys.exit(cli_main(sys.argv))


if __name__ == "__main__":
    main()
