import sys

from fusioncenter.cli import main

sys.exit(main())
