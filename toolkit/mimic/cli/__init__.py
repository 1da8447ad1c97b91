"""The `mimic` command line: thin Typer commands over the library core."""
