# Installs the five tools with their man pages and bash, zsh and fish
# completions under a prefix:
#
#     make install PREFIX=$HOME/.local      # default PREFIX: /usr/local
#     make uninstall PREFIX=$HOME/.local
#
# The man pages (man/) and completions (completions/) are generated from the
# tools' argument definitions and kept equal to them by the test
# `man_pages_match_the_argument_definitions`; the file formats' section-5
# pages (man/man5/) are made from their docs/ pages and kept equal to them by
# `format_man_pages_match_their_docs_pages`. BIN= installs tools built
# elsewhere (the install test passes its own).
PREFIX  ?= /usr/local
DESTDIR ?=
BIN     ?= target/release
TOOLS   := pat-from-image pat-info pat-tile polyfill3 scene-render
FORMATS := $(notdir $(wildcard man/man5/*.5))
ROOT    := $(DESTDIR)$(PREFIX)

SHELL := /bin/bash
.SHELLFLAGS := -o pipefail -ec
.PHONY: install uninstall build

build:
ifeq ($(BIN),target/release)
	cargo build --release --locked --bins
endif

install: build
	install -d $(ROOT)/bin $(ROOT)/share/man/man1 $(ROOT)/share/man/man5 \
	    $(ROOT)/share/bash-completion/completions $(ROOT)/share/zsh/site-functions \
	    $(ROOT)/share/fish/vendor_completions.d
	for t in $(TOOLS); do \
	    install -m 755 $(BIN)/$$t $(ROOT)/bin/$$t; \
	    install -m 644 man/$$t.1 $(ROOT)/share/man/man1/$$t.1; \
	    install -m 644 completions/bash/$$t $(ROOT)/share/bash-completion/completions/$$t; \
	    install -m 644 completions/zsh/_$$t $(ROOT)/share/zsh/site-functions/_$$t; \
	    install -m 644 completions/fish/$$t.fish $(ROOT)/share/fish/vendor_completions.d/$$t.fish; \
	done
	for f in $(FORMATS); do \
	    install -m 644 man/man5/$$f $(ROOT)/share/man/man5/$$f; \
	done

uninstall:
	for t in $(TOOLS); do \
	    rm -f $(ROOT)/bin/$$t $(ROOT)/share/man/man1/$$t.1 \
	        $(ROOT)/share/bash-completion/completions/$$t \
	        $(ROOT)/share/zsh/site-functions/_$$t \
	        $(ROOT)/share/fish/vendor_completions.d/$$t.fish; \
	done
	for f in $(FORMATS); do rm -f $(ROOT)/share/man/man5/$$f; done
