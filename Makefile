# The two commands of the README. Both install what they need first (scripts/install-deps.sh is
# idempotent), configure and build with the default CMake preset.
.PHONY: demo test deps build debug-test format format-check

deps:
	./scripts/install-deps.sh

build: deps
	cmake --preset default
	cmake --build --preset default

demo: build
	./scripts/demo.sh

test: build
	ctest --preset default

debug-test: deps
	cmake --preset debug
	cmake --build --preset debug
	ctest --preset debug

# Sources only: build trees (build/, build-debug/, build-fuzz/) hold generated files.
SOURCES = find . -path './build*' -prune -o -path ./.git -prune -o \( -name '*.cpp' -o -name '*.hpp' \) -print

format:
	$(SOURCES) | xargs clang-format -i

format-check:
	$(SOURCES) | xargs clang-format --dry-run --Werror
