from ifsforge.cli import run

# Guarded like the installed launcher: spawned Dask workers import the main module again.
if __name__ == "__main__":
    run()
