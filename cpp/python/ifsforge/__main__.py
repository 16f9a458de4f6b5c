from ifsforge.cli import run

run()
