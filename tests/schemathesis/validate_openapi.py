"""Validates an OpenAPI document (a file, or a URL) against the OpenAPI 3.1 meta-schema.

Schemathesis ships the meta-schema but does not refuse a document that breaks it, so this is
checked on its own: every error is printed with where it is, and the exit status says whether
there were any.
"""

import json
import sys
import urllib.request

from schemathesis.specs.openapi.definitions import OPENAPI_31_VALIDATOR


def main(location: str) -> int:
    if location.startswith("http"):
        with urllib.request.urlopen(location) as response:
            document = json.load(response)
    else:
        with open(location, encoding="utf-8") as file:
            document = json.load(file)
    errors = list(OPENAPI_31_VALIDATOR.iter_errors(document))
    for error in errors:
        pointer = "".join(
            "/" + str(part).replace("~", "~0").replace("/", "~1") for part in error.instance_path
        )
        print(f"openapi: {pointer}: {error.message}", file=sys.stderr)
    print(f"openapi: {location} is {'not ' if errors else ''}a valid OpenAPI 3.1 document")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
