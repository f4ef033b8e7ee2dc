/**
 * HyperFun syntax highlighting for CodeMirror: a stream tokenizer (the
 * language is line-oriented enough: `--` comments to the end of the line,
 * no block constructs that span tokens) and a highlight style.
 * Library functions are recognised from the kernel's table, so a name
 * the compiler would not know is not coloured as one.
 */
import { HighlightStyle, LanguageSupport, StreamLanguage, syntaxHighlighting, type StreamParser } from '@codemirror/language';
import { tags as t } from '@lezer/highlight';
import { BUILTINS, KEYWORDS } from './hf-syntax';
import { libraryFunction } from './library';

const keywords = new Set(KEYWORDS);
const builtins = new Set(BUILTINS);

const parser: StreamParser<Record<string, never>> = {
  name: 'hyperfun',
  startState: () => ({}),
  token(stream) {
    if (stream.eatSpace()) return null;
    if (stream.match('--')) {
      stream.skipToEnd();
      return 'comment';
    }
    if (stream.match(/^(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?/)) return 'number';
    if (stream.match(/^"[^"]*"?/)) return 'string';
    const word = stream.match(/^[A-Za-z][A-Za-z0-9_]*/) as RegExpMatchArray | null;
    if (word) {
      const w = word[0].toLowerCase();
      if (keywords.has(w)) return 'keyword';
      if (libraryFunction(w)) return 'function';
      if (builtins.has(w)) return 'builtin';
      if (w === 'x' || w === 'a' || w === 's') return 'atom';
      return 'variableName';
    }
    if (stream.match(/^(\/=|<=|>=|[|&\\~@])/)) return 'operatorKeyword';
    if (stream.match(/^[-+*/^=<>]/)) return 'operator';
    if (stream.match(/^[()[\]{}]/)) return 'bracket';
    stream.next();
    return 'punctuation';
  },
  languageData: { commentTokens: { line: '--' } },
  tokenTable: {
    function: t.function(t.variableName),
    builtin: t.standard(t.variableName),
    operatorKeyword: t.operatorKeyword,
  },
};

/** The stream language. */
export const hyperfunLanguage = StreamLanguage.define(parser);

const style = HighlightStyle.define([
  { tag: t.comment, class: 'hf-comment' },
  { tag: t.number, class: 'hf-number' },
  { tag: t.keyword, class: 'hf-keyword' },
  { tag: t.function(t.variableName), class: 'hf-function' },
  { tag: t.standard(t.variableName), class: 'hf-builtin' },
  { tag: t.atom, class: 'hf-atom' },
  { tag: t.operatorKeyword, class: 'hf-setop' },
  { tag: t.string, class: 'hf-string' },
]);

/** HyperFun: the language with its highlighting. */
export function hyperfun(): LanguageSupport {
  return new LanguageSupport(hyperfunLanguage, [syntaxHighlighting(style)]);
}
