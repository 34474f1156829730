#!/usr/bin/env python3
"""Function length check: lists the C++ functions longer than a limit, from braces.

Usage: funclen.py [--max N] [--allow PATH:NAME]... [--list] DIR_OR_FILE...

A function is a brace block at namespace or class level whose head has a parameter
list (not a control statement, a lambda or an initialiser). Its length counts its
lines from the head's brace to the closing one. Comments, strings (raw ones too) and
preprocessor lines are blanked first, so their braces do not count. Brace-initialised
members in a constructor's initialiser list are part of the head.

Exits 1 when a function not named by --allow is over the limit (a known long function
that someone is splitting: PATH:NAME, PATH as printed); --list prints every function
over the limit and exits 0.
"""
import argparse
import os
import re
import sys

CONTROL = re.compile(r'^\s*(if|for|while|switch|catch|else|do|try|return|namespace|class|struct|enum|union|extern)\b')
LAMBDA_TAIL = re.compile(r'\]\s*(\([^)]*\))?\s*(mutable\s*)?(noexcept\s*)?(->[^{]*)?$')
# `Foo::Foo(...) : a_(1), b_` before the `{` of `b_{2}`: a member's brace initialiser.
INIT_MEMBER = re.compile(r'\)\s*(noexcept\s*)?:(?!:).*[A-Za-z0-9_>]$')
TRAILING_QUALIFIER = re.compile(r'\b(const|override|final|noexcept|mutable)$')


def blank(src):
    """`src` with comments, string and character literals and preprocessor lines
    replaced by spaces (newlines kept, so line numbers stay)."""
    out = []
    i, n = 0, len(src)
    keep_newlines = lambda s: re.sub(r'[^\n]', ' ', s)
    while i < n:
        c = src[i]
        if src.startswith('//', i):
            j = src.find('\n', i)
            j = n if j < 0 else j
            out.append(' ' * (j - i))
            i = j
        elif src.startswith('/*', i):
            j = src.find('*/', i + 2)
            j = n if j < 0 else j + 2
            out.append(keep_newlines(src[i:j]))
            i = j
        elif src.startswith('R"', i) and (i == 0 or not (src[i - 1].isalnum() or src[i - 1] == '_')):
            m = re.match(r'R"([^(\s]*)\(', src[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = ')' + m.group(1) + '"'
            j = src.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append(keep_newlines(src[i:j]))
            i = j
        elif c in '"\'':
            if c == "'" and i > 0 and src[i - 1].isalnum():  # a digit separator: 1'000
                out.append(' ')
                i += 1
                continue
            j = i + 1
            while j < n and src[j] != c and src[j] != '\n':
                j += 2 if src[j] == '\\' else 1
            out.append(c + keep_newlines(src[i + 1:j]) + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    text = ''.join(out)
    # Preprocessor lines, with their continuations.
    return re.sub(r'(?m)^[ \t]*#(?:[^\n]*\\\n)*[^\n]*', lambda m: keep_newlines(m.group(0)), text)


def functions(path):
    """(first line, last line, name) of every function in the file."""
    s = blank(open(path, encoding='utf-8', errors='replace').read())
    stack = []  # (kind, start line, name): kind is 'func', 'init' or 'other'
    head_start = 0
    found = []
    line = 1
    for i, c in enumerate(s):
        if c == '\n':
            line += 1
        elif c == ';':
            head_start = i + 1
        elif c == '{':
            head = ' '.join(s[head_start:i].split())
            in_function = any(kind == 'func' for kind, _, _ in stack)
            kind = 'other'
            if not in_function and ')' in head and not CONTROL.match(head) and not head.endswith('=') \
                    and not LAMBDA_TAIL.search(head):
                before_params = head.split('(')[0]
                if '=' not in before_params or 'operator' in before_params:
                    if INIT_MEMBER.search(head) and not TRAILING_QUALIFIER.search(head):
                        kind = 'init'
                    else:
                        kind = 'func'
            name = re.sub(r'\s*\(.*', '', head).split(' ')[-1] if kind == 'func' else ''
            stack.append((kind, line, name))
            if kind != 'init':
                head_start = i + 1
        elif c == '}':
            if stack:
                kind, start, name = stack.pop()
                if kind == 'func':
                    found.append((start, line, name))
                if kind == 'init':
                    continue  # the head goes on to the body's brace
            head_start = i + 1
    return found


def sources(roots):
    for root in roots:
        if os.path.isfile(root):
            yield root
            continue
        for folder, dirs, files in os.walk(root):
            dirs.sort()
            for f in sorted(files):
                if f.endswith(('.cpp', '.h', '.cc', '.hpp', '.in')):
                    yield os.path.join(folder, f)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--max', type=int, default=80, help='longest allowed function, in lines (default 80)')
    ap.add_argument('--allow', action='append', default=[], metavar='PATH:NAME',
                    help='a function allowed to be longer, for now')
    ap.add_argument('--list', action='store_true', help='list the long functions, exit 0')
    ap.add_argument('roots', nargs='+')
    args = ap.parse_args()
    allowed = set(args.allow)
    long_ones = []
    for path in sources(args.roots):
        for start, end, name in functions(path):
            if end - start + 1 > args.max:
                long_ones.append((end - start + 1, path, start, name))
    failed = False
    seen_allowed = set()
    for length, path, start, name in sorted(long_ones, reverse=True):
        key = path + ':' + name
        if key in allowed:
            seen_allowed.add(key)
            note = ' (allowed for now)'
        else:
            failed = True
            note = ''
        print(f'{path}:{start}: {name} is {length} lines (limit {args.max}){note}')
    for key in sorted(allowed - seen_allowed):
        print(f'note: {key} is allowed to be long but no longer is (take it off the list)')
    return 0 if args.list or not failed else 1


if __name__ == '__main__':
    sys.exit(main())
