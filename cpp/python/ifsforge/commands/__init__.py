"""Sub-commands of the ifsforge CLI, one module each (see ifsforge.cli)."""
