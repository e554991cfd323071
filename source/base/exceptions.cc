#include <nlmech/base/exceptions.h>

#include <deal.II/base/exceptions.h>

#include <boost/core/demangle.hpp>

#include <new>
#include <sstream>
#include <typeinfo>

namespace nlmech
{
  using namespace dealii;

  namespace
  {
    std::string trim(const std::string &s)
    {
      const auto begin = s.find_first_not_of(" \t\r\n");
      if (begin == std::string::npos)
        return "";
      return s.substr(begin, s.find_last_not_of(" \t\r\n") - begin + 1);
    }
  } // namespace

  std::string message_of(const std::exception &e)
  {
    if (const auto *d = dynamic_cast<const ExceptionBase *>(&e))
      {
        std::ostringstream info;
        d->print_info(info);
        std::string text = trim(info.str());
        // Collapse deal.II's indentation and line breaks into one readable paragraph.
        std::string collapsed;
        bool        space = false;
        for (char c : text)
          if (c == '\n' || c == ' ' || c == '\t')
            space = true;
          else
            {
              if (space && !collapsed.empty())
                collapsed += ' ';
              collapsed += c;
              space = false;
            }
        return collapsed.empty() ? d->get_exc_name() : collapsed;
      }
    return e.what();
  }

  std::string describe_current_exception()
  {
    try
      {
        throw;
      }
    catch (const ExceptionBase &e)
      {
        return message_of(e);
      }
    catch (const std::bad_alloc &)
      {
        return "out of memory (std::bad_alloc): the problem is too large for this machine";
      }
    catch (const std::exception &e)
      {
        return std::string(e.what()) + " (an exception of type " + boost::core::demangle(typeid(e).name()) +
               ")";
      }
    catch (const std::string &text)
      {
        return text + " (an exception of type std::string)";
      }
    catch (const char *text)
      {
        return std::string(text) + " (an exception of type const char *)";
      }
    catch (const int code)
      {
        return "an exception of type int with value " + std::to_string(code);
      }
    catch (...)
      {
        return "an exception of unknown type";
      }
  }
} // namespace nlmech
