"""`python -m meshsmith ...` is the `meshsmith` command."""
from .cli import main

raise SystemExit(main())
