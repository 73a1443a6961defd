"""One module per command group; each exposes `commands = [...]`."""
