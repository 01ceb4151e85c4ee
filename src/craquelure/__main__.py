import sys

from craquelure.cli import main

sys.exit(main())
