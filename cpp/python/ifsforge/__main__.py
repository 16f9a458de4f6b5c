import sys

from ifsforge.cli import main

sys.exit(main())
